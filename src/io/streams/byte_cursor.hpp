// Whole small binary files and a bounded cursor over their bytes: the surface and overlay
// readers (FreeSurfer, VTK) read fields of either byte order without ever reading past the end.
#pragma once
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>

namespace imx::detail {

// The bytes of `file` (a regular file), after check_memory for its size. Throws imx::FileError
// naming it when it cannot be read.
std::string read_file_bytes(const std::filesystem::path& file);

class ByteCursor {
 public:
  // `what` names the file in errors; `big_endian` is the byte order of the fields.
  ByteCursor(std::string_view bytes, std::string what, bool big_endian)
      : bytes_(bytes), what_(std::move(what)), big_(big_endian) {}

  size_t position() const { return pos_; }
  size_t remaining() const { return bytes_.size() - pos_; }
  bool at_end() const { return pos_ == bytes_.size(); }
  const std::string& what() const { return what_; }

  // Throws imx::Error "WHAT: the file ends inside FIELD (N bytes needed at byte P, M left)".
  void need(uint64_t n, std::string_view field) const;

  // One field of type T (integer or float) in the cursor's byte order.
  template <class T>
  T read(std::string_view field) {
    need(sizeof(T), field);
    T value;
    char raw[sizeof(T)];
    std::memcpy(raw, bytes_.data() + pos_, sizeof(T));
    if (big_ != (std::endian::native == std::endian::big)) std::reverse(raw, raw + sizeof(T));
    std::memcpy(&value, raw, sizeof(T));
    pos_ += sizeof(T);
    return value;
  }

  std::string_view take(size_t n, std::string_view field) {
    need(n, field);
    std::string_view out = bytes_.substr(pos_, n);
    pos_ += n;
    return out;
  }

  // The text up to the next '\n' (which is consumed), of at most `limit` bytes.
  std::string_view line(std::string_view field, size_t limit);

 private:
  std::string_view bytes_;
  std::string what_;
  bool big_;
  size_t pos_ = 0;
};

}  // namespace imx::detail
