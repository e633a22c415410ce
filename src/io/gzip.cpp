#include "io/gzip.hpp"

#include <algorithm>
#include <memory>
#include <vector>

#include <fmt/format.h>
#include <zlib.h>

#include "intermix/error.hpp"

namespace imx::detail {

namespace {

constexpr size_t kChunk = size_t{1} << 18;
// zlib counts in 32-bit uInt: feed larger outputs in pieces below that.
constexpr size_t kMaxPiece = size_t{1} << 30;
// Inflated bytes past what the caller asked for that are still read to reach the checksum.
constexpr size_t kMaxSurplus = size_t{1} << 20;

std::string zlib_message(const z_stream& z, int code) {
  return z.msg ? z.msg : fmt::format("zlib error {}", code);
}

}  // namespace

void check_inflatable(size_t needed, size_t compressed, const std::string& what) {
  if (static_cast<double>(needed) > kMaxInflateRatio * static_cast<double>(compressed) + 4096.0)
    throw Error(
        fmt::format("{}: the header asks for {} bytes of data, but {} compressed bytes cannot "
                    "inflate to that much (deflate expands at most about 1032:1)",
                    what, needed, compressed));
}

size_t gunzip(std::istream& in, size_t skip, std::span<uint8_t> out, const std::string& what) {
  z_stream z{};
  // 15 + 32: largest window, and detect the gzip or zlib wrapper from the header.
  if (inflateInit2(&z, 15 + 32) != Z_OK) throw Error(fmt::format("{}: zlib failed to start", what));
  std::unique_ptr<z_stream, int (*)(z_stream*)> guard(&z, inflateEnd);

  std::vector<uint8_t> input(kChunk);
  std::vector<uint8_t> scratch(kChunk);
  size_t written = 0, surplus = 0;
  bool input_done = false;
  auto refill = [&] {
    in.read(reinterpret_cast<char*>(input.data()), static_cast<std::streamsize>(input.size()));
    z.next_in = input.data();
    z.avail_in = static_cast<uInt>(in.gcount());
    if (z.avail_in == 0) input_done = true;
  };
  // Inflate to the end of the stream even once `out` is full, so that zlib checks the trailer's
  // checksum: a corrupt stream must not pass because the header asked for less than it holds.
  while (true) {
    if (z.avail_in == 0 && !input_done) refill();
    const bool skipping = skip > 0, full = !skipping && written == out.size();
    uint8_t* dst = skipping || full ? scratch.data() : out.data() + written;
    size_t room = skipping ? std::min(skip, scratch.size())
                  : full   ? scratch.size()
                           : std::min(out.size() - written, kMaxPiece);
    z.next_out = dst;
    z.avail_out = static_cast<uInt>(room);
    int rc = inflate(&z, Z_NO_FLUSH);
    size_t produced = room - z.avail_out;
    if (skipping)
      skip -= produced;
    else if (full)
      surplus += produced;
    else
      written += produced;
    if (surplus > kMaxSurplus)
      throw Error(fmt::format("{}: the compressed data holds more than the {} bytes expected", what,
                              out.size()));
    if (rc == Z_STREAM_END) {
      // Concatenated gzip members form one stream; anything else after the end is ignored.
      if (z.avail_in == 0 && !input_done) refill();
      if (z.avail_in >= 2 && z.next_in[0] == 0x1f && z.next_in[1] == 0x8b) {
        inflateReset(&z);
        continue;
      }
      break;
    }
    if (rc == Z_BUF_ERROR && z.avail_in == 0) {
      if (!input_done) continue;        // needs more input: the loop reads it
      if (written < out.size()) break;  // truncated: the caller reports the shortfall
      throw Error(
          fmt::format("{}: the gzip data ends before its checksum (truncated file?)", what));
    }
    if (rc != Z_OK)
      throw Error(fmt::format("{}: corrupt gzip data ({})", what, zlib_message(z, rc)));
  }
  return written;
}

void gzip(std::span<const std::span<const uint8_t>> parts, std::ostream& out, int level,
          const std::string& what) {
  z_stream z{};
  // 15 + 16: largest window with a gzip wrapper, as NRRD's "encoding: gzip" expects.
  if (deflateInit2(&z, level, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw Error(fmt::format("{}: zlib failed to start", what));
  std::unique_ptr<z_stream, int (*)(z_stream*)> guard(&z, deflateEnd);

  std::vector<uint8_t> buffer(kChunk);
  size_t part = 0, consumed = 0;  // the part being fed and how much of it zlib has
  int rc = Z_OK;
  do {
    while (z.avail_in == 0 && part < parts.size()) {
      if (consumed == parts[part].size()) {
        ++part;
        consumed = 0;
        continue;
      }
      size_t piece = std::min(parts[part].size() - consumed, kMaxPiece);
      z.next_in = const_cast<Bytef*>(parts[part].data() + consumed);
      z.avail_in = static_cast<uInt>(piece);
      consumed += piece;
    }
    const bool last = part == parts.size() ||
                      (part + 1 == parts.size() && consumed == parts[part].size());
    z.next_out = buffer.data();
    z.avail_out = static_cast<uInt>(buffer.size());
    rc = deflate(&z, last ? Z_FINISH : Z_NO_FLUSH);
    if (rc == Z_STREAM_ERROR) throw Error(fmt::format("{}: zlib failed to compress", what));
    out.write(reinterpret_cast<const char*>(buffer.data()),
              static_cast<std::streamsize>(buffer.size() - z.avail_out));
    if (!out) throw Error(fmt::format("{}: writing failed (disk full?)", what));
  } while (rc != Z_STREAM_END);
}

void gzip(std::span<const uint8_t> data, std::ostream& out, int level, const std::string& what) {
  const std::span<const uint8_t> parts[] = {data};
  gzip(parts, out, level, what);
}

}  // namespace imx::detail
