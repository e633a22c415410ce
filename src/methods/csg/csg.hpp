// The csg method (SPEC §8, seed 004): CSG of volumes and closed meshes evaluated per ray.
#pragma once
#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {

Image render_csg(const Scene& scene, int spp, const RenderOptions& options);

}  // namespace imx
