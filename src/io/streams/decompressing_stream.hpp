// DecompressingStream: what the gzip and bzip2 streams share over their decoders: reading into
// a buffer, skipping, and reading to the end so that the format's checksum is checked.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace imx::detail {

class DecompressingStream {
 public:
  virtual ~DecompressingStream() = default;
  DecompressingStream(const DecompressingStream&) = delete;
  DecompressingStream& operator=(const DecompressingStream&) = delete;

  // Decompresses into `out`; returns how many bytes it holds, fewer only where the data ends.
  size_t read(std::span<uint8_t> out) { return pull(out.data(), out.size()); }
  // Decompresses `n` bytes and drops them; returns how many, fewer only where the data ends.
  size_t skip(size_t n);
  // Decompresses the rest so that the format's checksum is checked: a corrupt stream must not
  // pass because the caller wanted less than it holds. Throws when more than 1 MiB is left
  // (`expected`: the bytes the caller wanted, for the message) or the data stops before its end.
  void finish(size_t expected);

 protected:
  // Messages say "WHAT: the DATA holds more than ..." and "... ends before END (truncated
  // file?)".
  DecompressingStream(std::string what, const char* data, const char* end);
  // Decompresses up to `room` bytes into `dst`, setting ended_ (and truncated_) at the end.
  virtual size_t pull(uint8_t* dst, size_t room) = 0;

  std::string what_;
  bool ended_ = false;      // the stream's end, or its data stopped (truncated)
  bool truncated_ = false;  // the data stopped before the stream's end

 private:
  const char* data_;
  const char* end_;
  std::vector<uint8_t> scratch_;
};

}  // namespace imx::detail
