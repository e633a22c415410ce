// FragmentContext: what the fragment-buffer methods prepare once per frame on top of FrameSetup.
#pragma once
#include "frame/frame_setup.hpp"
#include "frame/hybrid_composite.hpp"
#include "frame/surface_thickness.hpp"
#include "intermix/scene.hpp"

namespace imx {

// The depth range [near, far] every ray's geometry lies in: bounds of the whole scene, as a
// single-pass OIT method needs them for its depth weights before seeing any fragment.
struct DepthRange {
  float near = 1.0f, far = 1000.0f;
};

struct FragmentContext {
  FrameSetup frame;
  HybridParams hybrid;         // volume step (render.step_mm, else the smallest voxel pitch), ERT
  SurfaceThickness thickness;  // zero for the exact methods, else per object (SPEC §6)
  DepthRange depth_range;

  // `method` names the method in errors; `zero_thickness` makes every fragment a surface.
  FragmentContext(const Scene& scene, const char* method, bool zero_thickness);
};

// Slabs a ray's scratch arrays hold before they fold (tail), per array.
inline constexpr int kRayScratchSlabs = 4096;

InSlabInterpolation interpolation_of(const RenderSettings& render);

}  // namespace imx
