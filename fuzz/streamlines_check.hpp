// What every streamline reader promises (intermix/streamlines.hpp), checked on whatever it
// accepted: offsets from 0, ascending, ending at the point count; at least 2 finite points per
// streamline; one value per point or per streamline in every named array.
#pragma once
#include <cmath>

#include "intermix/streamlines.hpp"

namespace imx::fuzz {

inline void check_streamlines(const Streamlines& s) {
  if (s.offsets.empty() || s.offsets.front() != 0 || s.offsets.back() != s.points.size())
    __builtin_trap();
  for (size_t i = 0; i < s.count(); ++i)
    if (s.offsets[i + 1] < s.offsets[i] + 2) __builtin_trap();
  for (const glm::vec3& p : s.points)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) __builtin_trap();
  for (const StreamlineValues& v : s.point_values)
    if (v.values.size() != s.points.size()) __builtin_trap();
  for (const StreamlineValues& v : s.streamline_values)
    if (v.values.size() != s.count()) __builtin_trap();
}

}  // namespace imx::fuzz
