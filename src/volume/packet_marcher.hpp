// composite_packets: VolumeMarcher::composite (SlabExtent::grid) for many rays through one
// volume, a packet at a time in the lanes of the widest SIMD target the machine has (one kernel
// source, simd_targets.hpp). Pure: no allocation, no exceptions.
#pragma once
#include <span>

#include <glm/glm.hpp>

#include "core/blinn_phong.hpp"
#include "core/camera_model.hpp"
#include "core/ray.hpp"
#include "slab/slab_array.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/volume_marcher.hpp"

namespace imx {

// One ray of a batch and its part [t0, t1] of the volume (PreparedVolume::intersect()).
struct PacketRay {
  Ray ray;
  float t0 = 0.0f;
  float t1 = -1.0f;
};

// The camera rays through points `at` of a block of 4 x 2 pixels (x + i, y + j), i < 4, j < 2,
// (the centres by default, or one sample's offset in each) as out[j * 4 + i], with the arithmetic
// the AVX2 lanes had (CameraModel::ray up to float rounding). Leaves t0 and t1 alone.
class PacketCamera {
 public:
  explicit PacketCamera(const CameraModel& camera);
  void block(int x, int y, PacketRay* out, glm::vec2 at = glm::vec2(0.5f)) const;

 private:
  glm::vec3 at_, per_x_, per_y_;  // CameraModel::pixel_basis in floats
  glm::vec3 eye_, forward_;
  bool perspective_;
  bool wide_;  // fused as the lanes fuse, in hardware (wide_scalar.hpp), where the machine can
};

// Whether composite_packets() marches volume `v` with `lights` in vector lanes (on any SIMD
// target, the scalar one included): it needs a pre-integration table or a label map (without
// no-data voxels), when shading is on at most RayShading::kMaxLights lights and a tabulated
// specular power (shininess of at least 1), and a grid of at least 2 voxels a side whose gathers
// fit int32 offsets (fewer than 2^31 voxels, 2^31 / 6 with int16 gradients) and, with skipping,
// fewer than 2^24 bricks. Otherwise it marches each ray with VolumeMarcher, with the same results.
bool packet_marching_supported(const PreparedVolume& v, std::span<const ShadingLight> lights);

// Sets each ray's [t0, t1] to PreparedVolume::intersect(ray), in groups of eight rays with the
// arithmetic the AVX2 lanes had (the same interval up to float rounding).
void intersect_packets(const PreparedVolume& v, std::span<PacketRay> rays);

// out[i] = the premultiplied colour that VolumeMarcher(v, rays[i].ray, rays[i].t0, rays[i].t1,
// step, lights, extent).composite() makes from (0, 0, 0, 0) with termination at `ert`, up to
// float reassociation. Rays go in packets of the target's lanes (1 to 16) in batch order, so
// neighbouring rays should be consecutive (a tile in blocks of 4 x 2 pixels). `out` holds
// rays.size() colours. SlabExtent::visible shades each piece where its light comes from (one point,
// or two a standard deviation either side of its centre), as the slab methods' marcher does; the
// extents themselves do not change a composite.
void composite_packets(const PreparedVolume& v, std::span<const PacketRay> rays, float step,
                       std::span<const ShadingLight> lights, float ert, std::span<glm::vec4> out,
                       SlabExtent extent = SlabExtent::grid);

// Where march_slab_packets puts each ray's visible pieces, in depth order: take(i, slab) for
// ray i returns false when that ray needs no more.
class SlabSink {
 public:
  virtual bool take(size_t ray, const Slab& slab) = 0;

 protected:
  ~SlabSink() = default;
};

// The slabs VolumeMarcher(v, ray, t0, t1, step, lights, SlabExtent::visible) emits for each ray,
// into `sink`, until the ray's composite of them reaches `ert` (never when ert > 1) or the sink
// declines: a packet of rays at a time in lanes where composite_packets would take them (and not a
// label map), up to float rounding. Rays as composite_packets wants them.
void march_slab_packets(const PreparedVolume& v, std::span<const PacketRay> rays, float step,
                        std::span<const ShadingLight> lights, float ert, SlabSink& sink);

// Where collect_packets puts each ray's slabs: lists[i] for ray i, folded as `overflow` says
// once full.
struct SlabCollection {
  std::span<SlabList> lists;
  Overflow overflow = Overflow::tail;
};

// The slab methods' own array of volume `v` for many rays: for rays[i], the slabs that
// VolumeMarcher(v, ray, t0, t1, step, lights, SlabExtent::visible) emits, gathered by
// collect_slabs into collection.lists[i] until the volume alone reaches `a_ert` (ert_reached),
// a packet of rays at a time in lanes where composite_packets would take them (and not a label
// map), up to float rounding. Rays as composite_packets wants them.
void collect_packets(const PreparedVolume& v, std::span<const PacketRay> rays, float step,
                     std::span<const ShadingLight> lights, float a_ert,
                     const SlabCollection& collection);

}  // namespace imx
