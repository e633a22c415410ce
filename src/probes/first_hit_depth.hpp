// First-hit depth images of single objects, the input of the intersection-band metric.
#pragma once
#include <string>

#include "intermix/image.hpp"
#include "intermix/scene.hpp"

namespace imx {

// Per pixel (ray through the centre) the depth t where object `name` alone first reaches
// `opacity` (dvr volumes: accumulated front to back at its voxel pitch; iso volumes: the
// crossing; projections: their depth; meshes, planes and tubes: the nearest fragment), in the red
// channel; +inf where it is not reached. Throws imx::Error for an unknown name.
Image first_hit_depth(const Scene& scene, const std::string& name, float opacity = 0.5f,
                      int threads = 0);

}  // namespace imx
