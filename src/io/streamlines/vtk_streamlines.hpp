// Streamlines from the polylines (LINES cells) of VTK polydata files: legacy .vtk, ASCII or
// BINARY, and XML .vtp, read by the same parsers as the VTK meshes.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "intermix/streamlines.hpp"

namespace imx::detail {

// Each line cell one streamline, through its points in the cell's order; single-component point
// data scalars become point_values, single-component cell data scalars of the lines
// streamline_values. Placed as the VTK mesh readers place the same file's triangles: LPS unless
// the file says SPACE=RAS (3D Slicer's tag), where x and y are negated. A line cell that names a
// point the file lacks, or cell data that is not one tuple per cell, is an imx::Error; `notes`
// gets a line for the space, for each kind of streamline left out (fewer than 2 points, points
// that are not finite) and for arrays left unread.
Streamlines read_vtk_streamlines(const std::filesystem::path& file,
                                 std::vector<std::string>& notes);

}  // namespace imx::detail
