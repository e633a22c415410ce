#include "dist/swap_schedule.hpp"

namespace imx {

int swap_group(int ranks) {
  int p = 1;
  while (p * 2 <= ranks) p *= 2;
  return p;
}

SwapSchedule binary_swap(int ranks, int rank, size_t pixels) {
  SwapSchedule s;
  const int group = swap_group(ranks);
  if (rank >= group) {
    s.fold_to = rank - group;
    return s;
  }
  if (rank + group < ranks) s.fold_from = rank + group;
  PixelRange range{0, pixels};
  for (int bit = 1; bit < group; bit *= 2) {
    const size_t mid = range.first + range.size() / 2;
    const PixelRange low{range.first, mid}, high{mid, range.end};
    SwapRound r;
    r.partner = rank ^ bit;
    const bool lower = (rank & bit) == 0;
    r.keep = lower ? low : high;
    r.send = lower ? high : low;
    r.first = lower;
    s.rounds.push_back(r);
    range = r.keep;
  }
  s.result = range;
  return s;
}

}  // namespace imx
