// bzip2 streams through libbz2: decompressing voxel data from a file piece by piece.
#pragma once
#include <cstddef>
#include <cstdint>
#include <istream>
#include <memory>
#include <span>
#include <string>

#include "io/streams/decompressing_stream.hpp"

namespace imx::detail {

// bzip2 data read from `in` and decompressed piece by piece, as GzipStream does for gzip, so
// that a caller can keep only the parts it wants with bounded memory: two 256 KiB buffers and
// libbz2's own state (about 3.6 MiB for a 900k block). Concatenated bzip2 streams (pbzip2's
// output) read as one; anything else after the end is ignored. Every block's CRC and the
// stream's combined CRC are checked by libbz2 as the data is read. Throws imx::Error naming
// `what` when the data is corrupt.
class Bzip2Stream final : public DecompressingStream {
 public:
  Bzip2Stream(std::istream& in, std::string what);
  ~Bzip2Stream() override;

 private:
  size_t pull(uint8_t* dst, size_t room) override;
  void refill();
  void restart();

  struct State;
  std::istream& in_;
  std::unique_ptr<State> state_;
};

// bzip2 expands at most about 1.4 million to 1 (a 900k block of one repeated byte, run-length
// coded to 46 MB, compresses to some 32 bytes); larger claims are corrupt or hostile headers.
// The bound leaves room for hand-made streams with smaller tables.
inline constexpr double kMaxBzip2Ratio = 5.0e6;

// Throws imx::Error naming `what` unless `compressed` bytes of bzip2 data could hold `needed`
// bytes: catches corrupt or hostile headers before anything is allocated.
void check_bzip2_inflatable(size_t needed, size_t compressed, const std::string& what);

}  // namespace imx::detail
