// The first bytes of a volume file whose header may be gzip-compressed (.nii.gz, .mgz): read
// through zlib when the file starts with gzip's magic, so that the extension is no guess.
#pragma once
#include <cstddef>
#include <filesystem>
#include <string>

namespace imx::detail {

struct FileHead {
  std::string bytes;     // up to the size asked for; fewer only where the (inflated) data ends
  bool gzipped = false;  // the file starts with gzip's magic (1f 8b)
};

// Up to `size` bytes from the start of `file`, inflated when it is gzip data. Only what the
// header needs is inflated: the data's checksum is checked later, by the voxel read. Throws
// imx::FileError naming `what` when it cannot be opened, imx::Error when its gzip data is
// corrupt.
FileHead read_file_head(const std::filesystem::path& file, size_t size, const std::string& what);

}  // namespace imx::detail
