// VTK polylines as streamlines (io/streamlines/vtk_streamlines.hpp): the input is a legacy .vtk
// or an XML .vtp file (found by its first bytes). Line cells must name only the file's points
// and cell data must be one tuple per cell; what it returns must be whole: offsets from 0 to the
// point count, rising, every streamline of 2 points or more, every point finite, one value per
// point of each point array and one per streamline of each streamline array.
#include <cmath>
#include <exception>
#include <string>
#include <vector>

#include "harness.hpp"
#include "io/streamlines/vtk_streamlines.hpp"

namespace {

void check_streamlines(const imx::Streamlines& s) {
  if (s.offsets.empty() || s.offsets.front() != 0 || s.offsets.back() != s.points.size())
    __builtin_trap();
  for (size_t i = 0; i < s.count(); ++i)
    if (s.offsets[i + 1] < s.offsets[i] + 2) __builtin_trap();
  for (const glm::vec3& p : s.points)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) __builtin_trap();
  for (const imx::StreamlineValues& v : s.point_values)
    if (v.values.size() != s.points.size()) __builtin_trap();
  for (const imx::StreamlineValues& v : s.streamline_values)
    if (v.values.size() != s.count()) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const std::filesystem::path file = dir.write("in.vtk", data, size);
  try {
    std::vector<std::string> notes;
    check_streamlines(imx::detail::read_vtk_streamlines(file, notes));
    accepted("streamlines");
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
