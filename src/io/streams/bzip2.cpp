#include "io/streams/bzip2.hpp"

#include <bzlib.h>

#include <algorithm>
#include <cstring>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx::detail {

namespace {

constexpr size_t kChunk = size_t{1} << 18;
// libbz2 counts in unsigned int: feed larger outputs in pieces below that.
constexpr size_t kMaxPiece = size_t{1} << 30;

std::string bzip2_message(int code) {
  switch (code) {
    case BZ_DATA_ERROR:
      return "a block or stream CRC does not match, or the data is malformed";
    case BZ_DATA_ERROR_MAGIC:
      return "it does not start with the bzip2 signature 'BZh'";
    case BZ_MEM_ERROR:
      return "libbz2 ran out of memory";
    default:
      return fmt::format("libbz2 error {}", code);
  }
}

}  // namespace

void check_bzip2_inflatable(size_t needed, size_t compressed, const std::string& what) {
  if (static_cast<double>(needed) > kMaxBzip2Ratio * static_cast<double>(compressed) + 4096.0)
    throw Error(
        fmt::format("{}: the header asks for {} bytes of data, but {} bytes of bzip2 data cannot "
                    "decompress to that much (bzip2 expands at most about 1.4 million to 1)",
                    what, needed, compressed));
}

struct Bzip2Stream::State {
  bz_stream z{};
  bool started = false;
  std::vector<char> input = std::vector<char>(kChunk);
  bool input_done = false;  // `in` has nothing more
};

Bzip2Stream::Bzip2Stream(std::istream& in, std::string what)
    : DecompressingStream(std::move(what), "bzip2 data", "its end-of-stream marker"),
      in_(in),
      state_(std::make_unique<State>()) {
  // small = 0: the fast decoder (about 3.6 MiB at most); verbosity 0.
  if (BZ2_bzDecompressInit(&state_->z, 0, 0) != BZ_OK)
    throw Error(fmt::format("{}: libbz2 failed to start", what_));
  state_->started = true;
}

Bzip2Stream::~Bzip2Stream() {
  if (state_->started) BZ2_bzDecompressEnd(&state_->z);
}

void Bzip2Stream::refill() {
  State& s = *state_;
  in_.read(s.input.data(), static_cast<std::streamsize>(s.input.size()));
  s.z.next_in = s.input.data();
  s.z.avail_in = static_cast<unsigned>(in_.gcount());
  if (s.z.avail_in == 0) s.input_done = true;
}

// A new decoder for the next of concatenated streams, keeping the input not yet consumed.
void Bzip2Stream::restart() {
  State& s = *state_;
  char* next_in = s.z.next_in;
  const unsigned avail_in = s.z.avail_in;
  BZ2_bzDecompressEnd(&s.z);
  s.started = false;
  s.z = bz_stream{};
  if (BZ2_bzDecompressInit(&s.z, 0, 0) != BZ_OK)
    throw Error(fmt::format("{}: libbz2 failed to start", what_));
  s.started = true;
  s.z.next_in = next_in;
  s.z.avail_in = avail_in;
}

size_t Bzip2Stream::pull(uint8_t* dst, size_t room) {
  State& s = *state_;
  bz_stream& z = s.z;
  size_t done = 0;
  while (done < room && !ended_) {
    if (z.avail_in == 0 && !s.input_done) refill();
    const size_t asked = std::min(room - done, kMaxPiece);
    z.next_out = reinterpret_cast<char*>(dst + done);
    z.avail_out = static_cast<unsigned>(asked);
    const unsigned had_in = z.avail_in;
    const int rc = BZ2_bzDecompress(&z);
    const size_t produced = asked - z.avail_out;
    done += produced;
    if (rc == BZ_STREAM_END) {
      // Concatenated streams form one; anything else after the end is ignored.
      if (z.avail_in < 3 && !s.input_done) {
        // Keep the unread tail at the front of the buffer and top it up to see the signature.
        std::memmove(s.input.data(), z.next_in, z.avail_in);
        in_.read(s.input.data() + z.avail_in,
                 static_cast<std::streamsize>(s.input.size() - z.avail_in));
        const auto got = static_cast<unsigned>(in_.gcount());
        if (got == 0) s.input_done = true;
        z.next_in = s.input.data();
        z.avail_in += got;
      }
      if (z.avail_in >= 3 && std::memcmp(z.next_in, "BZh", 3) == 0) {
        restart();
        continue;
      }
      ended_ = true;
      break;
    }
    if (rc != BZ_OK)
      throw Error(fmt::format("{}: corrupt bzip2 data ({})", what_, bzip2_message(rc)));
    // No input left, none to come and nothing produced: the stream stops before its end.
    if (produced == 0 && z.avail_in == 0 && had_in == 0 && s.input_done) {
      ended_ = truncated_ = true;
      break;
    }
  }
  return done;
}

}  // namespace imx::detail
