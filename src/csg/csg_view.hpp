// CsgView: what the per-ray CSG kernels read of a frame's expression: primitive maps, the
// expression as a program, the clipping states, presence modes and interior media.
#pragma once
#include <cstdint>
#include <span>

#include <glm/vec3.hpp>

#include "csg/clip_state.hpp"
#include "csg/csg_expr.hpp"
#include "csg/state_table.hpp"

namespace imx {

// A mesh primitive's interior medium for one frame (opacity 0: none).
struct CsgMedium {
  glm::vec3 color{0.0f};
  float opacity = 0.0f;  // of unit_distance mm
  float unit_distance = 1.0f;
};

// What the per-ray CSG kernels read: spans into the frame's tables (DESIGN principle 2).
struct CsgView {
  std::span<const CsgInstr> program;            // the expression itself (the reference's oracle)
  std::span<const ClipState> states;            // the clipping states (the csg method's test)
  std::span<const int8_t> primitive_of_object;  // Scene::order index -> primitive, -1: none
  std::span<const int8_t> primitive_of_volume;  // FrameSetup::volumes index -> primitive, -1
  std::span<const int8_t> volume_of_primitive;  // primitive -> FrameSetup::volumes index, -1
  std::span<const CsgMedium> medium;            // per primitive; only meshes have one
  PrimitiveMask geometric = 0;  // primitives present wherever they enclose a point (region)
  PrimitiveMask meshes = 0;
  PrimitiveMask used = 0;           // every primitive of the expression
  PrimitiveMask with_medium = 0;    // meshes with an interior medium
  float presence_threshold = 0.0f;  // TF opacity per unit_distance a present volume exceeds
  int primitive_count = 0;

  // E(present) by the clipping states. The table may treat "nothing present" as a don't care
  // (csg_simplify full); the expression is false there.
  bool value(PrimitiveMask present) const { return present != 0 && matches_any(states, present); }
};

}  // namespace imx
