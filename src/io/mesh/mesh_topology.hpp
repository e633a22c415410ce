// Mesh topology: whether a triangle mesh encloses a region, and which way it faces.
#pragma once
#include <cstddef>

#include "intermix/mesh.hpp"

namespace imx {

// The closedness and orientation of a mesh after welding exactly equal positions.
struct MeshTopology {
  size_t open_edges = 0;      // welded undirected edges not used by exactly two triangles
  size_t unpaired_edges = 0;  // directed edges without their reverse (inconsistent winding)
  double signed_volume = 0;   // mm^3; positive when the triangles face outward

  // A closed, consistently wound surface: inside and outside are well defined.
  bool closed() const { return open_edges == 0 && unpaired_edges == 0; }
};

// Welds exactly equal positions (primitives duplicate them along seams and sharp edges), drops
// triangles that collapse to an edge or a point after welding, counts the edges and integrates
// the signed volume by the divergence theorem in double precision.
MeshTopology check_closed(const Mesh& mesh);

// The same surface facing the other way: reversed triangle winding, negated normals.
Mesh flipped(const Mesh& mesh);

}  // namespace imx
