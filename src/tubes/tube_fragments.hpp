// Tube fragments: the shaded crossings of one sample ray with a streamline object's tubes.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "intermix/scene.hpp"
#include "raster/fragment.hpp"
#include "tubes/tube_geometry.hpp"

namespace imx {

// What colours and lets through a streamline object's fragments in one frame: its fields with
// their values and ranges looked up once.
struct TubeLook {
  const StreamlineObject* object = nullptr;
  const TubeGeometry* geometry = nullptr;
  const float* point_values = nullptr;       // point_value colouring
  const float* streamline_values = nullptr;  // streamline_value colouring
  float value_low = 0.0f, value_high = 1.0f;
  std::vector<int32_t> group_of;  // per streamline: its first group, or -1 (group colouring)
  bool shaded = true;             // false: colour 0, for clip passes
  size_t hits_per_query = 32;     // nearest hits asked at a time (1 for opaque tubes)
};

// The look of `object` drawn with `geometry`. Throws imx::Error naming the object when its
// colouring names values its streamlines do not have.
TubeLook make_tube_look(const StreamlineObject& object, const TubeGeometry& geometry);

// The opacity of one surface crossing: a tube crossing is an entry and an exit, so each carries
// the part whose square lets through what the object's per-crossing opacity does.
float tube_fragment_alpha(float crossing_opacity);

// Appends to `out` the fragments of `ray` with the tubes in front of t_max, nearest first,
// until what they let through falls below 1/1024 (what lies behind can change no colour by
// more). `object` is its Scene::order index.
void append_tube_fragments(const TubeLook& look, const Ray& ray, float t_max, uint32_t object,
                           std::span<const ShadingLight> lights, std::vector<Fragment>& out);

}  // namespace imx
