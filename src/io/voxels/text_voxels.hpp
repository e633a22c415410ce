// Voxel data written as text (NRRD's ascii and hex encodings), decoded to the bytes of elements.
#pragma once
#include <cstddef>
#include <cstdint>
#include <istream>
#include <span>
#include <string>

#include "io/voxels/raw_voxels.hpp"

namespace imx::detail {

// Numbers in text, one element each, read from `in`'s position: separated by any whitespace
// (any count of them per line) or commas, decoded to elements of `type` in host byte order.
// Integer types take integers ("7", "-3", also "7.0" or "7e2", which are whole), in the type's
// range; float and double take any number, "nan" and "inf" included, a finite one in the
// type's range. Anything else is refused, with imx::Error naming `what`, the value's index and
// the text, never read as some other number.
class AsciiValues {
 public:
  AsciiValues(std::istream& in, RawType type, std::string what);

  // Decodes out.size() / raw_type_size(type) values into `out`. Throws when one is not a
  // number of the type, or the text ends first (`expected`: how many the header gives).
  void read(std::span<uint8_t> out, uint64_t expected);
  // Decodes `count` values and drops them, checking each as read does.
  void skip(uint64_t count, uint64_t expected);
  // Throws unless nothing but separators is left: more values than the header gives mean its
  // sizes are wrong, not that the rest may be dropped.
  void expect_end(uint64_t expected);
  uint64_t values_read() const { return index_; }

 private:
  bool next_token();  // false at the end of the text
  void decode(uint8_t* dst);

  std::streambuf& in_;
  RawType type_;
  std::string what_;
  std::string token_;
  uint64_t index_ = 0;
};

// Bytes written as pairs of hexadecimal digits (either case), read from `in`'s position;
// whitespace anywhere between the digits is ignored. Anything else is refused with imx::Error
// naming `what`.
class HexBytes {
 public:
  HexBytes(std::istream& in, std::string what);

  // Decodes out.size() bytes into `out`; throws when the text ends first (`expected`: how many
  // bytes the header gives) or holds anything but digits and whitespace.
  void read(std::span<uint8_t> out, uint64_t expected);
  void skip(uint64_t count, uint64_t expected);
  // Throws unless nothing but whitespace is left.
  void expect_end(uint64_t expected);

 private:
  int next_digit();  // 0..15, or -1 at the end of the text

  std::streambuf& in_;
  std::string what_;
  uint64_t index_ = 0;  // bytes decoded so far
};

}  // namespace imx::detail
