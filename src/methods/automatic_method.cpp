#include "methods/automatic_method.hpp"

namespace imx {

MethodChoice choose_method(const Scene& scene) {
  if (scene.csg) return {"csg", "a csg block"};
  if (scene.render.mixing == "exclusive") return {"csg", "exclusive mixing"};
  if (scene.volumes.empty()) return {"dfb-sfm", "surfaces only"};
  if (!scene.meshes.empty()) return {"kbuffer-ofm", "volumes with meshes"};
  if (!scene.planes.empty()) return {"peel", "volumes with planes"};
  return {"mdvr", "volumes only"};
}

}  // namespace imx
