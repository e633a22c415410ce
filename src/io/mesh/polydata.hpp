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

struct PolyDataFile {
  Mesh mesh;  // positions, triangles, normals when the file has them (colours never)
  std::vector<MeshPointData> point_data;
  std::optional<MeshSpace> space;  // 3D Slicer's SPACE=LPS / SPACE=RAS, where the file says
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
// 3D Slicer's SPACE= tag.
PolyDataFile read_vtk_legacy(const std::filesystem::path& file);

// XML PolyData (.vtp): <VTKFile type="PolyData">, any number of pieces, ascii, base64 binary or
// appended (raw or base64) data, uncompressed or zlib-compressed (vtkZLibDataCompressor), UInt32
// or UInt64 headers. Reads Points, Polys and Strips, PointData arrays (Normals: the mesh's
// normals) and the SPACE field 3D Slicer writes in FieldData.
PolyDataFile read_vtp(const std::filesystem::path& file);

}  // namespace imx::detail
