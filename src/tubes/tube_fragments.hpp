// Tube fragments: the shaded crossings of one sample ray with a streamline object's tubes.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "intermix/scene.hpp"
#include "raster/fragment.hpp"
#include "tubes/tube_clip.hpp"
#include "tubes/tube_clip_meshes.hpp"
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
  std::vector<int32_t> group_of;         // per streamline: its first group, or -1 (group colouring)
  size_t hits_per_query = 32;            // nearest hits asked at a time (1 for opaque tubes)
  bool every_crossing = false;           // a CSG primitive: all crossings, so windings close
  std::shared_ptr<const TubeClip> clip;  // the object's clip planes; null without any
  std::shared_ptr<const TubeClipMeshes> clip_meshes;  // its clip meshes; null without any
  // Silhouette coverage (tube_coverage.hpp): a tube covers the part of a pixel of width
  // footprint(t) = footprint_at_0 + footprint_per_mm * t that lies within its radius.
  bool silhouette_aa = false;
  float footprint_at_0 = 0.0f, footprint_per_mm = 0.0f;
};

// The look of `object` drawn with `geometry`; `meshes` are the scene's, which its clip meshes
// index. Throws imx::Error naming the object when its colouring names values its streamlines
// do not have, or a clip mesh is not one of `meshes`.
TubeLook make_tube_look(const StreamlineObject& object, const TubeGeometry& geometry,
                        std::span<const MeshObject> meshes = {});
// The same without tubes (geometry null), for colours along the streamlines themselves.
TubeLook make_tube_look(const StreamlineObject& object);

// The colour before lighting at `u` (0..1) along the segment from point `point` (a
// Streamlines::points index) of streamline `streamline`.
glm::vec3 streamline_colour(const TubeLook& look, uint32_t streamline, uint32_t point, float u);

// The opacity of one surface crossing: a tube crossing is an entry and an exit, so each carries
// the part whose square lets through what the object's per-crossing opacity does.
float tube_fragment_alpha(float crossing_opacity);

// The opacity per crossing of the tube around `segment` (its group's, or the object's).
float tube_crossing_opacity(const TubeLook& look, uint32_t segment);

// How many fragments of `object` a ray can need: past that many crossings what they let through
// is below the bound (1/1024), so later ones change no colour by more. 1 for opaque tubes;
// SIZE_MAX when a crossing opacity of 0 leaves no bound.
size_t tube_fragments_needed(const StreamlineObject& object);

// Appends to `out` the fragments of `ray` with the tubes in front of t_max, nearest first,
// until what they let through falls below 1/1024 (what lies behind can change no colour by
// more), or all of them with look.every_crossing. `object` is its Scene::order index. With clip
// planes and clip meshes, only crossings that every plane and mesh keeps, and a cap fragment where
// the ray meets a plane or a mesh inside a tube.
void append_tube_fragments(const TubeLook& look, const Ray& ray, float t_max, uint32_t object,
                           std::span<const ShadingLight> lights, std::vector<Fragment>& out);

}  // namespace imx
