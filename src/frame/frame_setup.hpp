// FrameSetup: what every method prepares once per frame (camera, volumes, lights, step, clip
// geometry).
#pragma once
#include <span>
#include <vector>

#include "core/blinn_phong.hpp"
#include "core/camera_model.hpp"
#include "frame/brick_coverage.hpp"
#include "frame/clip_plan.hpp"
#include "intermix/scene.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/ray_volumes.hpp"

namespace imx {

// Steps one ray may take through one volume.
inline constexpr double kMaxStepsPerRay = 1 << 17;

struct FrameSetup {
  CameraModel camera;
  std::vector<PreparedVolume> volumes;  // Scene::volumes order
  std::vector<ShadingLight> lights;
  double min_pitch = 1.0;  // smallest voxel spacing over the scene's volumes, mm (1 without any)
  std::vector<BrickCoverage> coverage;  // per volume, from accelerate() (empty before)
  ClipPlan clip;                        // the volumes' clip meshes

  explicit FrameSetup(const Scene& scene);

  // Gives every volume the skipping structures, pre-integration table and gradients that
  // `settings` asks for at ray step `step` mm (from caches that outlive the frame), and the
  // screen blocks its occupied bricks can show in.
  void accelerate(float step, const MarchSettings& settings);
  // The same with volume k prepared at steps[k] mm (one entry per volume).
  void accelerate(std::span<const float> steps, const MarchSettings& settings);

  // The step each volume is cast at: `common` for all, or with `per_volume`
  // (render.sampling=per-volume) `common` times the whole number of times the smallest voxel
  // pitch fits into the volume's own pitch (at least once).
  std::vector<float> volume_steps(double common, bool per_volume) const;

  // Whether volume v's march may find something in pixel (x, y): an occupied brick of it can
  // show there (BrickCoverage), or accelerate() has not run.
  bool may_show(size_t v, int x, int y) const {
    return v >= coverage.size() || coverage[v].covered(x, y);
  }

  // may_show() of every volume as one bit each.
  VolumeMask volumes_may_show(int x, int y) const {
    VolumeMask mask = kEveryVolume;
    for (size_t k = 0; k < coverage.size(); ++k)
      if (!may_show(k, x, y)) mask &= ~(VolumeMask{1} << k);
    return mask;
  }

  // The ray step in mm: render.step_mm when set, else the smallest voxel pitch times
  // `pitch_fraction`. Throws imx::Error when a ray through some volume would take more than
  // kMaxStepsPerRay steps (a step of 1e-9 mm, or voxels of 0.001 x 0.001 x 1000 mm), naming the
  // volume, the step and where it comes from.
  double ray_step(const RenderSettings& settings, double pitch_fraction = 1.0) const;

  // Throws imx::Error naming `method` when the scene has more volumes than a ray can hold.
  void require_per_sample_support(const char* method) const;
};

}  // namespace imx
