// VTK polylines as streamlines (io/streamlines/vtk_streamlines.hpp): the input is a legacy .vtk
// or an XML .vtp file (found by its first bytes). Line cells must name only the file's points
// and cell data must be one tuple per cell; what it returns must be whole: offsets from 0 to the
// point count, rising, every streamline of 2 points or more, every point finite, one value per
// point of each point array and one per streamline of each streamline array.
#include "io/streamlines/vtk_streamlines.hpp"
#include "streamlines_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return imx::fuzz::fuzz_streamline_reader(data, size, "in.vtk", imx::detail::read_vtk_streamlines);
}
