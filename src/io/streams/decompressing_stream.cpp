#include "io/streams/decompressing_stream.hpp"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx::detail {

namespace {

constexpr size_t kScratch = size_t{1} << 18;
// Decompressed bytes past what the caller asked for that are still read to reach the checksum.
constexpr size_t kMaxSurplus = size_t{1} << 20;

}  // namespace

DecompressingStream::DecompressingStream(std::string what, const char* data, const char* end)
    : what_(std::move(what)), data_(data), end_(end), scratch_(kScratch) {}

size_t DecompressingStream::skip(size_t n) {
  size_t done = 0;
  while (done < n) {
    const size_t want = std::min(n - done, scratch_.size());
    const size_t got = pull(scratch_.data(), want);
    done += got;
    if (got < want) break;
  }
  return done;
}

void DecompressingStream::finish(size_t expected) {
  size_t surplus = 0;
  while (!ended_) {
    surplus += pull(scratch_.data(), scratch_.size());
    if (surplus > kMaxSurplus)
      throw Error(
          fmt::format("{}: the {} holds more than the {} bytes expected", what_, data_, expected));
  }
  if (truncated_)
    throw Error(fmt::format("{}: the {} ends before {} (truncated file?)", what_, data_, end_));
}

}  // namespace imx::detail
