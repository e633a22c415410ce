// What VTK polydata files (legacy .vtk, XML .vtp) hold for intermix, and the cell-to-triangle
// rules both readers share.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "intermix/io.hpp"
#include "intermix/mesh.hpp"

namespace imx::detail {

// Polyline cells (LINES), kept only where the caller asks (the streamline reader): line i runs
// through the point indices indices[offsets[i] .. offsets[i + 1]), as the file gives them (not
// yet checked against the points).
struct PolyLines {
  std::vector<int64_t> indices;
  std::vector<uint64_t> offsets{0};
};

struct PolyDataFile {
  Mesh mesh;  // positions, triangles, normals when the file has them (colours never)
  std::vector<MeshPointData> point_data;
  std::optional<MeshSpace> space;  // 3D Slicer's SPACE=LPS / SPACE=RAS, where the file says

  // With keep_lines only: the lines, and each cell data array's tuples of those lines.
  PolyLines lines;
  std::vector<MeshPointData> line_data;
};

// Appends polygon `cell` (vertex indices, checked against `vertex_count`) fan-triangulated, as
// PLY faces are; `what` names the file and the cell in errors. Points and lines are not
// polygons: cells of fewer than 3 vertices are refused.
void add_polygon(Mesh& mesh, std::span<const int64_t> cell, uint64_t vertex_count,
                 const std::string& what);
// Appends a triangle strip's triangles, every other one reversed so that all face one way, as
// VTK does; triangles with a repeated vertex (VTK's way to turn a strip) are left out.
void add_strip(Mesh& mesh, std::span<const int64_t> cell, uint64_t vertex_count,
               const std::string& what);

// Legacy VTK (.vtk): "# vtk DataFile Version 2.0 to 5.1", ASCII or BINARY (big-endian),
// DATASET POLYDATA. Reads POINTS, POLYGONS and TRIANGLE_STRIPS (VERTICES and LINES are left
// out), POINT_DATA's SCALARS (each a point data array), NORMALS (the mesh's normals) and FIELD
// arrays; other attributes and CELL_DATA are checked and skipped. The title line carries
// 3D Slicer's SPACE= tag. With `keep_lines`, the LINES cells and the CELL_DATA arrays' values
// of those lines are kept too (polygons and strips are then counted, not triangulated), and a
// CELL_DATA array that is not one tuple per cell is an error.
PolyDataFile read_vtk_legacy(const std::filesystem::path& file, bool keep_lines = false);

// XML PolyData (.vtp): <VTKFile type="PolyData">, any number of pieces, ascii, base64 binary or
// appended (raw or base64) data, uncompressed or zlib-compressed (vtkZLibDataCompressor), UInt32
// or UInt64 headers. Reads Points, Polys and Strips, PointData arrays (Normals: the mesh's
// normals) and the SPACE field 3D Slicer writes in FieldData. With `keep_lines`, the Lines
// cells (checked offsets) and the CellData arrays' values of those lines are kept too, and Polys
// and Strips are left out.
PolyDataFile read_vtp(const std::filesystem::path& file, bool keep_lines = false);

}  // namespace imx::detail
