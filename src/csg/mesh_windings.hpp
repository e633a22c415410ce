// CsgWindings: which closed CSG meshes enclose the current point of a sample ray, by non-zero
// winding counts over the ray's fragments (SPEC §8). Pure, fixed-size, no allocation.
#pragma once
#include <algorithm>
#include <bit>
#include <cstdint>
#include <span>

#include "csg/clip_state.hpp"
#include "raster/fragment.hpp"

namespace imx {

struct CsgWindings {
  int winding[kMaxCsgPrimitives];  // valid for the primitives in `met`
  PrimitiveMask met = 0;           // mesh primitives with a fragment in the row
  PrimitiveMask inside = 0;        // bit k: mesh primitive k encloses the point (winding > 0)
  bool inconsistent = false;       // a start winding was negative: a fragment of the row was lost

  // The windings at t = 0. `primitive_of_object` maps Scene::order indices to primitives (-1:
  // not in the expression). A ray that starts inside a mesh (the eye in a cutter, its entry
  // clipped by the near plane) meets more back faces than front faces: #back - #front is the
  // winding at the eye, whatever the meshes overlap. Only the meshes the row meets are touched:
  // this runs for every sample ray.
  CsgWindings(std::span<const Fragment> row, std::span<const int8_t> primitive_of_object) {
    for (const Fragment& f : row)
      if (int k = primitive_of(f, primitive_of_object); k >= 0) {
        const PrimitiveMask bit = PrimitiveMask{1} << k;
        if (!(met & bit)) winding[k] = 0;
        met |= bit;
        winding[k] += f.front_facing ? -1 : 1;
      }
    for (PrimitiveMask m = met; m; m &= m - 1) {
      const int k = std::countr_zero(m);
      if (winding[k] < 0) {
        winding[k] = 0;
        inconsistent = true;
      }
      if (winding[k] > 0) inside |= PrimitiveMask{1} << k;
    }
  }

  // Passes one fragment of the row; false when it is not a CSG mesh's.
  bool pass(const Fragment& f, std::span<const int8_t> primitive_of_object) {
    const int k = primitive_of(f, primitive_of_object);
    if (k < 0) return false;
    winding[k] += f.front_facing ? 1 : -1;
    if (winding[k] < 0) {
      winding[k] = 0;
      inconsistent = true;
    }
    const PrimitiveMask bit = PrimitiveMask{1} << k;
    inside = winding[k] > 0 ? inside | bit : inside & ~bit;
    return true;
  }

  static int primitive_of(const Fragment& f, std::span<const int8_t> primitive_of_object) {
    return f.object < primitive_of_object.size() ? primitive_of_object[f.object] : -1;
  }
};

}  // namespace imx
