#include "io/streams/gzip.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <fstream>
#include <memory>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <zlib.h>

#include "intermix/error.hpp"
#include "io/streams/input_file.hpp"

namespace imx::detail {

namespace {

constexpr size_t kChunk = size_t{1} << 18;
// zlib counts in 32-bit uInt: feed larger outputs in pieces below that.
constexpr size_t kMaxPiece = size_t{1} << 30;

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

struct GzipStream::State {
  z_stream z{};
  std::vector<uint8_t> input = std::vector<uint8_t>(kChunk);
  bool input_done = false;  // `in` has nothing more
};

GzipStream::GzipStream(std::istream& in, std::string what)
    : DecompressingStream(std::move(what), "gzip data", "its checksum"),
      in_(in),
      state_(std::make_unique<State>()) {
  // 15 + 32: largest window, and detect the gzip or zlib wrapper from the header.
  if (inflateInit2(&state_->z, 15 + 32) != Z_OK)
    throw Error(fmt::format("{}: zlib failed to start", what_));
}

GzipStream::~GzipStream() {
  inflateEnd(&state_->z);
}

void GzipStream::refill() {
  State& s = *state_;
  in_.read(reinterpret_cast<char*>(s.input.data()), static_cast<std::streamsize>(s.input.size()));
  s.z.next_in = s.input.data();
  s.z.avail_in = static_cast<uInt>(in_.gcount());
  if (s.z.avail_in == 0) s.input_done = true;
}

size_t GzipStream::pull(uint8_t* dst, size_t room) {
  State& s = *state_;
  z_stream& z = s.z;
  size_t done = 0;
  while (done < room && !ended_) {
    if (z.avail_in == 0 && !s.input_done) refill();
    const size_t asked = std::min(room - done, kMaxPiece);
    z.next_out = dst + done;
    z.avail_out = static_cast<uInt>(asked);
    int rc = inflate(&z, Z_NO_FLUSH);
    done += asked - z.avail_out;
    if (rc == Z_STREAM_END) {
      // Concatenated gzip members form one stream; anything else after the end is ignored.
      if (z.avail_in == 0 && !s.input_done) refill();
      if (z.avail_in >= 2 && z.next_in[0] == 0x1f && z.next_in[1] == 0x8b) {
        inflateReset(&z);
        continue;
      }
      ended_ = true;
      break;
    }
    if (rc == Z_BUF_ERROR && z.avail_in == 0) {
      if (!s.input_done) continue;  // needs more input: the loop reads it
      ended_ = truncated_ = true;
      break;
    }
    if (rc != Z_OK)
      throw Error(fmt::format("{}: corrupt gzip data ({})", what_, zlib_message(z, rc)));
  }
  return done;
}

size_t gunzip(std::istream& in, size_t skip, std::span<uint8_t> out, const std::string& what) {
  GzipStream stream(in, what);
  if (stream.skip(skip) < skip) return 0;  // truncated: the caller reports the shortfall
  const size_t written = stream.read(out);
  if (written == out.size()) stream.finish(out.size());
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
    const bool last =
        part == parts.size() || (part + 1 == parts.size() && consumed == parts[part].size());
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

void gunzip_file(const std::filesystem::path& gz, const std::filesystem::path& out,
                 uint64_t max_bytes, const std::string& what, const std::string& too_large) {
  std::ifstream in = open_input_stream(gz, what);
  std::ofstream file(out, std::ios::binary);
  if (!file) throw FileError(fmt::format("{}: cannot write its inflated copy", what), errno);
  GzipStream stream(in, what);
  std::vector<uint8_t> buffer(size_t{1} << 20);
  uint64_t total = 0;
  while (size_t got = stream.read(buffer)) {
    total += got;
    if (total > max_bytes)
      throw Error(
          fmt::format("{}: inflates to more than {} bytes: {}", what, max_bytes, too_large));
    file.write(reinterpret_cast<const char*>(buffer.data()), static_cast<std::streamsize>(got));
    if (!file) throw FileError(fmt::format("{}: cannot write its inflated copy", what), errno);
    if (got < buffer.size()) break;
  }
  stream.finish(static_cast<size_t>(total));
}

std::filesystem::path make_inflate_folder(const std::string& what) {
  std::error_code ec;
  const std::string pattern =
      (std::filesystem::temp_directory_path(ec) / "intermix-gz-XXXXXX").string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  if (ec || ::mkdtemp(name.data()) == nullptr)
    throw FileError(fmt::format("{}: cannot make a temporary folder to inflate it into", what),
                    errno);
  return name.data();
}

}  // namespace imx::detail
