#include "io/streams/bounded_inflate.hpp"

#include <algorithm>
#include <limits>

#include <fmt/format.h>
#include <zlib.h>

#include "intermix/error.hpp"

namespace imx::detail {

void inflate_exactly(std::span<const uint8_t> stored, std::span<uint8_t> out, const char* kind,
                     const std::string& what) {
  z_stream z{};
  if (inflateInit2(&z, 15 + 32) != Z_OK) throw Error(fmt::format("{}: zlib failed to start", what));
  struct End {
    z_stream* z;
    ~End() { inflateEnd(z); }
  } end{&z};
  // zlib counts in 32-bit uInt: both sides are fed in pieces below that.
  size_t in_pos = 0, out_pos = 0;
  uint8_t extra = 0;  // one byte past the claim tells a bomb from data that fits
  int rc = Z_OK;
  while (rc != Z_STREAM_END) {
    if (z.avail_in == 0 && in_pos < stored.size()) {
      const size_t n = std::min<size_t>(stored.size() - in_pos, std::numeric_limits<uInt>::max());
      z.next_in = const_cast<Bytef*>(stored.data() + in_pos);
      z.avail_in = static_cast<uInt>(n);
      in_pos += n;
    }
    const bool full = out_pos == out.size();
    if (full) {
      z.next_out = &extra;
      z.avail_out = 1;
    } else {
      const size_t n = std::min<size_t>(out.size() - out_pos, std::numeric_limits<uInt>::max());
      z.next_out = out.data() + out_pos;
      z.avail_out = static_cast<uInt>(n);
    }
    const uInt before = z.avail_out, before_in = z.avail_in;
    rc = inflate(&z, Z_NO_FLUSH);
    const size_t produced = before - z.avail_out;
    if (full && produced > 0)
      throw Error(fmt::format("{}: {} decompresses to more than the {} bytes expected", what, kind,
                              out.size()));
    out_pos += full ? 0 : produced;
    if (rc == Z_STREAM_END) break;
    if (rc == Z_NEED_DICT || rc == Z_DATA_ERROR || rc == Z_MEM_ERROR)
      throw Error(fmt::format("{}: corrupt {}: its compressed data does not inflate", what, kind));
    if (produced == 0 && before_in == z.avail_in) {
      if (z.avail_in == 0 && in_pos == stored.size())
        throw Error(fmt::format("{}: truncated {}: the data ends after {} of {} bytes", what, kind,
                                out_pos, out.size()));
      throw Error(fmt::format("{}: corrupt {} (no progress)", what, kind));
    }
  }
  if (out_pos != out.size())
    throw Error(fmt::format("{}: {} decompresses to {} bytes, expected {}", what, kind, out_pos,
                            out.size()));
}

}  // namespace imx::detail
