// SwapSchedule: binary-swap compositing of R images (Ma et al.'s schedule, R any count): ranks
// past the largest power of two P first send their whole image to rank r - P; then in round k
// each of the P ranks trades half of its current pixel range with rank r ^ 2^k. Every rank
// computes the same schedule from (R, rank, pixels), so no schedule is ever sent.
#pragma once
#include <cstddef>
#include <vector>

namespace imx {

struct PixelRange {
  size_t first = 0, end = 0;  // [first, end), in row-major pixel order
  size_t size() const { return end - first; }
  bool operator==(const PixelRange&) const = default;
};

struct SwapRound {
  int partner = -1;
  PixelRange keep;     // merged here: the partner sends its arrays of this range
  PixelRange send;     // sent to the partner, which keeps it
  bool first = false;  // this rank's arrays go in front of the partner's in the merge call
};

struct SwapSchedule {
  int fold_to = -1;    // >= 0: send the whole image there, then take no further part
  int fold_from = -1;  // >= 0: merge that rank's whole image first
  std::vector<SwapRound> rounds;
  PixelRange result;  // the range this rank composites at the end (empty if folded)
};

// The largest power of two not above `ranks` (>= 1).
int swap_group(int ranks);

SwapSchedule binary_swap(int ranks, int rank, size_t pixels);

}  // namespace imx
