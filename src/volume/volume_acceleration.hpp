// VolumeAcceleration: what a volume's ray marcher reads besides the voxels, and how it is built.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "volume/brick_occupancy.hpp"
#include "volume/gradient_volume.hpp"
#include "volume/preintegration_table.hpp"
#include "volume/tf_emptiness.hpp"
#include "volume/tf_lut.hpp"

namespace imx {

struct VolumeData;
struct VolumeObject;
struct RenderSettings;

enum class SkipMode : uint8_t { none, bricks, distance };
enum class Classification : uint8_t { preintegrated, post };
enum class GradientSource : uint8_t { automatic, on_the_fly, precomputed };

// What `automatic` lets a gradient copy take besides a quarter of the voxels' bytes: a volume
// then holds at most 1.25x its voxels + 200 MiB. Measured (docs/performance.md): the copy is
// 9-21% faster than central differences on the fly with packets up to 157 MB of voxels (30% one
// ray at a time), level at 530 MB and half as fast at 1.26 GB, where it takes 3.8 GB and 12 s.
inline constexpr uint64_t kGradientCopyAllowance = uint64_t{200} << 20;
// Whether shading normals of `data` come from a GradientVolume under `source` (a frame whose
// rays all march in lanes asks for on_the_fly instead: accelerate_for_packets): `automatic`
// precomputes them while the copy (GradientVolume::bytes_at_most) fits kGradientCopyAllowance
// plus a quarter of the voxels, and a quarter of the memory budget.
bool precomputes_gradients(GradientSource source, const VolumeData& data);

struct MarchSettings {
  SkipMode skip = SkipMode::distance;
  Classification classification = Classification::preintegrated;
  GradientSource gradients = GradientSource::automatic;
  int brick_size = 8;

  // The render block's choices (render.skipping, classification, gradients, brick_size).
  static MarchSettings from(const RenderSettings& render);
};

// Shared, immutable structures: a frame holds them while tables may be evicted from the caches.
struct VolumeAcceleration {
  SkipMode skip = SkipMode::none;
  std::shared_ptr<const BrickMinMax> ranges;          // null when skip == none
  std::shared_ptr<const BrickOccupancy> occupancy;    // null when skip == none
  std::shared_ptr<const TfEmptiness> emptiness;       // null when skip == none
  std::shared_ptr<const PreintegrationTable> preint;  // null for post-classification
  std::shared_ptr<const GradientVolume> gradients;    // null for on-the-fly gradients
};

// Whether a voxel array holds NaN or infinite voxels (non_finite_count() > 0): a float array is
// scanned once while its VolumeData lives (cached as brick ranges are), others never. Thread-safe.
bool has_non_finite_voxels(const std::shared_ptr<const VolumeData>& data);

// Builds or fetches from process-wide caches what `settings` asks for volume `v` with LUT `lut`
// at ray step `step` mm. The TF-independent parts (brick min/max, gradients) are kept per voxel
// array while its VolumeData lives; occupancy and pre-integration tables are rebuilt when the TF
// or the step changes (cheaply: no voxel access). Thread-safe.
VolumeAcceleration accelerate(const VolumeObject& v, const TfLut& lut, float step,
                              const MarchSettings& settings);

// One structure a volume holds resident for rendering, and its bytes.
struct ResidentPart {
  std::string name;
  uint64_t bytes = 0;
};
// What rendering `v` holds: its voxels (and colours) and each structure `a` has built for it, in
// that order; a structure `a` lacks is listed with 0 bytes (gradients: taken on the fly).
std::vector<ResidentPart> resident_parts(const VolumeObject& v, const VolumeAcceleration& a);

}  // namespace imx
