#include "methods/automatic_method.hpp"

namespace imx {

MethodChoice choose_method(const Scene& scene) {
  if (scene.csg) return {"csg", "a csg block"};
  if (scene.render.mixing == "exclusive") return {"csg", "exclusive mixing"};
  if (scene.volumes.empty()) return {"dfb-sfm", "surfaces only"};
  if (!scene.meshes.empty()) return {"zslab-hybrid", "volumes with meshes"};
  if (!scene.streamlines.empty()) return {"zslab-hybrid", "volumes with streamlines"};
  if (!scene.planes.empty()) return {"peel", "volumes with planes"};
  if (scene.volumes.size() > 1) return {"zslab-hybrid", "several volumes"};
  return {"mdvr", "volumes only"};
}

}  // namespace imx
