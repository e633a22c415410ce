#include "frame/surface_thickness.hpp"

namespace imx {

SurfaceThickness::SurfaceThickness(const Scene& scene, const CameraModel& camera, bool zero) {
  by_object_.assign(scene.order.size(), kAuto);
  for (size_t k = 0; k < scene.order.size(); ++k) {
    const ObjectRef& ref = scene.order[k];
    std::optional<double> d = scene.render.thickness;
    if (ref.kind == ObjectKind::mesh && ref.index >= 0 && size_t(ref.index) < scene.meshes.size())
      d = scene.meshes[ref.index].thickness ? scene.meshes[ref.index].thickness : d;
    if (ref.kind == ObjectKind::streamlines && ref.index >= 0 &&
        size_t(ref.index) < scene.streamlines.size())
      d = scene.streamlines[ref.index].thickness ? scene.streamlines[ref.index].thickness : d;
    if (ref.kind == ObjectKind::plane && ref.index >= 0 && size_t(ref.index) < scene.planes.size())
      d = scene.planes[ref.index].thickness ? scene.planes[ref.index].thickness : d;
    // Tubes' crossings are ray-traced, exact: auto is 0, as in zSlab (docs/zslab.md).
    if (zero || (ref.kind == ObjectKind::streamlines && !d))
      by_object_[k] = 0.0f;
    else if (d)
      by_object_[k] = static_cast<float>(std::max(*d, 0.0));
  }
  footprint_at_0_ = static_cast<float>(camera.pixel_footprint(0.0));
  footprint_per_mm_ = static_cast<float>(camera.pixel_footprint(1.0) - camera.pixel_footprint(0.0));
}

}  // namespace imx
