// The per-sample formulas of the volume march, written once over an arithmetic vocabulary `O`:
// ScalarOps (sample_ops.hpp: one float, the per-ray VolumeMarcher and VoxelGrid) or LaneOps
// (lanes-inl.hpp: one ray per SIMD lane, the packet kernels). A change to what a sample means is
// made in sample_formulas.inc, for both marchers: lerp, trilinear, dot3, light_of and
// blinn_phong. Pure: no allocation, no exceptions, no globals.
#pragma once
#include "intermix/scene.hpp"

#define IMX_FORMULA_ATTR
namespace imx::sample_formulas {
#include "volume/sample_formulas.inc"  // IWYU pragma: export
}  // namespace imx::sample_formulas
#undef IMX_FORMULA_ATTR
