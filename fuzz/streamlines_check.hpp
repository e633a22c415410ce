// What every streamline reader promises (intermix/streamlines.hpp), checked on whatever it
// accepted: offsets from 0, ascending, ending at the point count; at least 2 finite points per
// streamline; one value per point or per streamline in every named array; group members
// ascending and naming streamlines that exist.
#pragma once
#include <cmath>
#include <exception>
#include <string>
#include <vector>

#include "harness.hpp"

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
  for (const StreamlineGroup& g : s.groups)
    for (size_t i = 0; i < g.members.size(); ++i)
      if (g.members[i] >= s.count() || (i > 0 && g.members[i] <= g.members[i - 1]))
        __builtin_trap();
}

// One fuzz input read by a streamline reader from a file named `name`, what it accepts checked.
template <class Read>
int fuzz_streamline_reader(const uint8_t* data, size_t size, const char* name, Read read) {
  const ScratchDir& dir = scratch();
  dir.clear();
  const std::filesystem::path file = dir.write(name, data, size);
  try {
    std::vector<std::string> notes;
    check_streamlines(read(file, notes));
    accepted("streamlines");
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}

}  // namespace imx::fuzz
