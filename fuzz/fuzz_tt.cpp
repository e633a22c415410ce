// DSI Studio TinyTrack reader (io/streamlines/tt.hpp): the input is a .tt.gz file (gzip or raw
// MATLAB v4, found by its magic). Its matrix headers and streamline records must be checked
// against the bytes left; what it returns must be whole: offsets from 0 to the point count,
// rising, every streamline of 2 points or more, every point finite.
#include <cmath>
#include <exception>
#include <string>
#include <vector>

#include "harness.hpp"
#include "io/streamlines/tt.hpp"

namespace {

void check_streamlines(const imx::Streamlines& s) {
  if (s.offsets.empty() || s.offsets.front() != 0 || s.offsets.back() != s.points.size())
    __builtin_trap();
  for (size_t i = 0; i < s.count(); ++i)
    if (s.offsets[i + 1] < s.offsets[i] + 2) __builtin_trap();
  for (const glm::vec3& p : s.points)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const std::filesystem::path file = dir.write("in.tt.gz", data, size);
  try {
    std::vector<std::string> notes;
    check_streamlines(imx::detail::read_tt(file, notes));
    accepted("streamlines");
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
