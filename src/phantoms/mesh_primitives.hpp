// Mesh primitives (sphere, box, cylinder, torus, quad) centred at the origin, and mesh helpers.
#pragma once
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "intermix/mesh.hpp"

namespace imx {

// Every primitive has per-vertex normals and triangles wound counter-clockwise seen from
// outside. The closed ones (all but the quad) share every edge between exactly two triangles
// once coincident positions are welded (flat faces keep their own vertices for sharp normals).
// Invalid sizes or segment counts throw imx::Error; so does a mesh larger than the memory
// budget (check_memory), before it is made.

// The most segments a sphere, cylinder or torus may have. A sphere or torus of 1024 segments
// has about a million triangles: 24 MiB of mesh and about 340 MB at render time (the reference
// method, single-threaded); 4096 segments made 16 million and took more than 5 GB.
inline constexpr int kMaxPrimitiveSegments = 1024;

// A UV sphere: `segments` around the z axis and segments / 2 (at least 2) rings pole to pole.
Mesh make_sphere(double radius, int segments);

// An axis-aligned box with edge lengths `size`.
Mesh make_box(const glm::dvec3& size);

// A capped cylinder around the z axis, from z = -height/2 to height/2.
Mesh make_cylinder(double radius, double height, int segments);

// A torus around the z axis: `segments` around the axis and segments / 2 (at least 3) around
// the tube; needs minor < major so that it does not intersect itself.
Mesh make_torus(double major_radius, double minor_radius, int segments);

// A rectangle in the z = 0 plane, facing +z.
Mesh make_quad(const glm::dvec2& size);

// The mesh with positions transformed by the affine `m` and normals by its inverse transpose,
// renormalized, colours kept; a mirroring transform also reverses the winding so that it stays
// outward.
Mesh transform_mesh(const Mesh& mesh, const glm::dmat4& m);

}  // namespace imx
