// Members of a zip archive (stored or deflated, zip64 included), its central directory parsed
// here and deflate data inflated with zlib, piece by piece: a reader decides how many bytes each
// member must hold before anything is allocated or inflated.
#pragma once
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace imx::detail {

struct ZipMember {
  std::string name;              // its path inside the archive, '/'-separated
  uint64_t size = 0;             // inflated bytes, as the central directory says
  uint64_t compressed_size = 0;  // bytes it takes in the archive
  uint64_t header_offset = 0;    // of its local header
  uint32_t crc = 0;
  uint16_t method = 0;  // 0 stored, 8 deflate; others are refused when read
  uint16_t flags = 0;
  bool directory = false;  // a folder entry ("dps/"): no data
};

class ZipArchive {
 public:
  // Opens `file` and lists its central directory (the zip64 one where the archive has it).
  // Throws imx::FileError when it cannot be opened, imx::Error naming `what` when it is no zip
  // archive, spans several disks, or its directory is corrupt.
  ZipArchive(const std::filesystem::path& file, std::string what);
  ~ZipArchive();
  ZipArchive(const ZipArchive&) = delete;
  ZipArchive& operator=(const ZipArchive&) = delete;

  const std::vector<ZipMember>& members() const { return members_; }

  // Reads member `index` in order: open() it, read() consecutive pieces that together hold
  // exactly its size, then finish(), which checks that its data ends there and its CRC. Never
  // inflates more than one byte past the directory's size for it: the caller checks that size
  // before it allocates. Throws imx::Error naming `what` and the member for an encrypted member,
  // a method other than stored or deflate, a size the archive cannot hold (check_inflatable),
  // data that inflates to more or less than that size, corrupt data or a wrong CRC.
  void open(size_t index);
  void read(std::span<uint8_t> piece);
  void finish();

 private:
  [[noreturn]] void fail(const std::string& message) const;
  void read_at(uint64_t offset, void* dst, size_t n, const char* field);
  size_t fetch();  // the next compressed bytes into the inflater; 0 at the member's end

  struct Inflater;
  std::ifstream in_;
  std::string what_;
  uint64_t archive_bytes_ = 0;
  std::vector<ZipMember> members_;
  const ZipMember* current_ = nullptr;  // the open member
  uint64_t compressed_left_ = 0;        // its compressed bytes not yet read
  uint64_t read_ = 0;                   // its bytes read so far
  uint32_t crc_ = 0;                    // of those bytes
  std::unique_ptr<Inflater> inflater_;  // deflated members: zlib's raw inflate and its input
};

}  // namespace imx::detail
