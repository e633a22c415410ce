// Vertex normals for smooth shading: angle-weighted, with vertices split along creases.
#pragma once
#include <cstdint>
#include <vector>

#include "intermix/mesh.hpp"

namespace imx::detail {

// Replaces the mesh's normals (and reindexes it): vertices with equal position and colour are
// welded, each face corner gets the mean of the face normals around its vertex weighted by
// their corner angles, taken over the faces reached across edges whose faces meet at no more
// than `crease_deg` (0..180), and a vertex is split where the faces around it fall into
// several such groups. Positions and triangle winding are unchanged (geometry, closedness and
// facing stay the same); a degenerate triangle's corners get a zero normal ("none").
// `origin`, when given, receives for each new vertex the input vertex it came from.
void compute_vertex_normals(Mesh& mesh, double crease_deg, std::vector<uint32_t>* origin = nullptr);

}  // namespace imx::detail
