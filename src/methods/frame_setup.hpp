// FrameSetup: what every method prepares once per frame (camera, volumes, lights, step).
#pragma once
#include <vector>

#include "core/blinn_phong.hpp"
#include "core/camera_model.hpp"
#include "intermix/scene.hpp"
#include "volume/prepared_volume.hpp"

namespace imx {

struct FrameSetup {
  CameraModel camera;
  std::vector<PreparedVolume> volumes;  // Scene::volumes order
  std::vector<ShadingLight> lights;
  double min_pitch = 1.0;  // smallest voxel spacing over the scene's volumes, mm (1 without any)

  explicit FrameSetup(const Scene& scene);
};

}  // namespace imx
