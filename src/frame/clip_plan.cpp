#include "frame/clip_plan.hpp"

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx {

ClipPlan::ClipPlan(const Scene& scene)
    : slot_of_object_(scene.order.size(), -1), rule_(scene.volumes.size()) {
  std::vector<int> order_of_mesh(scene.meshes.size(), -1);
  for (size_t k = 0; k < scene.order.size(); ++k)
    if (scene.order[k].kind == ObjectKind::mesh && scene.order[k].index >= 0 &&
        static_cast<size_t>(scene.order[k].index) < order_of_mesh.size())
      order_of_mesh[scene.order[k].index] = static_cast<int>(k);
  int slots = 0;
  for (size_t v = 0; v < scene.volumes.size(); ++v) {
    for (const ClipMesh& c : scene.volumes[v].clip_meshes) {
      const std::string& name = scene.volumes[v].name;
      if (c.mesh < 0 || static_cast<size_t>(c.mesh) >= scene.meshes.size() ||
          order_of_mesh[c.mesh] < 0)
        throw Error(fmt::format("volume '{}': clip mesh index {} is not a mesh of the scene ({})",
                                name, c.mesh, scene.meshes.size()));
      int8_t& slot = slot_of_object_[order_of_mesh[c.mesh]];
      if (slot < 0) {
        if (slots == kMaxClipMeshes)
          throw Error(fmt::format("volume '{}': more than {} clip meshes in one scene", name,
                                  kMaxClipMeshes));
        slot = static_cast<int8_t>(slots++);
      }
      const PrimitiveMask bit = PrimitiveMask{1} << slot;
      if (c.keep_inside)
        rule_[v].ones |= bit;
      else
        rule_[v].zeros |= bit;
      any_ = true;
    }
  }
}

}  // namespace imx
