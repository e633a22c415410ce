// The streamlines a reader leaves out (fewer than 2 points, a coordinate that is not finite),
// counted as it goes and said once each in the notes.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace imx::detail {

class StreamlineDrops {
 public:
  void too_short(uint64_t index) { add(short_, index); }
  void not_finite(uint64_t index) { add(not_finite_, index); }

  // One note per reason: "FILE: 3 streamlines of fewer than 2 points dropped (the first:
  // streamline 7, counting from 0)".
  void report(const std::string& what, std::vector<std::string>& notes) const {
    if (short_.count > 0)
      notes.push_back(fmt::format(
          "{}: {} streamline{} of fewer than 2 points dropped (the first: streamline {}, "
          "counting from 0)",
          what, short_.count, short_.count == 1 ? "" : "s", short_.first));
    if (not_finite_.count > 0)
      notes.push_back(fmt::format(
          "{}: {} streamline{} with NaN or infinite coordinates dropped (the first: streamline "
          "{}, counting from 0)",
          what, not_finite_.count, not_finite_.count == 1 ? "" : "s", not_finite_.first));
  }

 private:
  struct Reason {
    uint64_t count = 0;
    uint64_t first = 0;
  };
  static void add(Reason& r, uint64_t index) {
    if (r.count++ == 0) r.first = index;
  }
  Reason short_, not_finite_;
};

}  // namespace imx::detail
