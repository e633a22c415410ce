// gzip streams through zlib: inflating voxel data from a file, deflating it onto a stream.
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <istream>
#include <memory>
#include <ostream>
#include <span>
#include <string>

#include "io/streams/decompressing_stream.hpp"

namespace imx::detail {

// gzip (or zlib) data read from `in` and inflated piece by piece, so that a caller can keep
// only the parts it wants (a box of voxels) with bounded memory: two 256 KiB buffers.
// Concatenated gzip members read as one stream; anything else after the end is ignored.
// Throws imx::Error naming `what` when the data is corrupt.
class GzipStream final : public DecompressingStream {
 public:
  GzipStream(std::istream& in, std::string what);
  ~GzipStream() override;

 private:
  size_t pull(uint8_t* dst, size_t room) override;
  void refill();

  struct State;
  std::istream& in_;
  std::unique_ptr<State> state_;
};

// Inflates gzip (or zlib) data read from `in`: the first `skip` bytes of output are dropped,
// the next go into `out`. Returns how many bytes were written to `out`, fewer than its size
// when the data ends early. Throws imx::Error naming `what` when the data is corrupt.
size_t gunzip(std::istream& in, size_t skip, std::span<uint8_t> out, const std::string& what);

// A new private folder (mode 0700) under the system's temporary folder for inflated copies of
// files that readers take only by name; the caller removes it. imx::FileError naming `what` when
// it cannot be made.
std::filesystem::path make_inflate_folder(const std::string& what);

// Inflates the gzip file `gz` into the new file `out` piece by piece. Throws imx::Error naming
// `what` when it would inflate to more than `max_bytes` ("WHAT: inflates to more than N bytes" and
// `too_large`, which says what that means), is corrupt or truncated; imx::FileError when a file
// cannot be opened or written.
void gunzip_file(const std::filesystem::path& gz, const std::filesystem::path& out,
                 uint64_t max_bytes, const std::string& what, const std::string& too_large);

// deflate cannot expand data more than about 1032:1; larger claims are corrupt headers.
inline constexpr double kMaxInflateRatio = 1100.0;

// Throws imx::Error naming `what` unless `compressed` bytes of deflate data could hold
// `needed` bytes: catches corrupt or hostile headers before anything is allocated.
void check_inflatable(size_t needed, size_t compressed, const std::string& what);

// Writes `data` to `out` as one gzip member at zlib's compression `level` (1 fast .. 9 small).
// Throws imx::Error naming `what` when zlib fails.
void gzip(std::span<const uint8_t> data, std::ostream& out, int level, const std::string& what);
// The same for data in several pieces, compressed as one: no copy to join them.
void gzip(std::span<const std::span<const uint8_t>> parts, std::ostream& out, int level,
          const std::string& what);

}  // namespace imx::detail
