// The 2-D reading views (axial, coronal, sagittal) of every volume of a scene: where a view's
// pixels lie in the patient, and what each shows: the first shown volume in grey through its
// window, each further one over it in its transfer function's colours (a PET over a CT), meshes
// cut by the plane as outlines. The viewer's reading views are these images.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "intermix/image.hpp"
#include "intermix/scene.hpp"
#include "raster/slab_sample.hpp"

namespace imx {

enum class SliceAxis { axial, coronal, sagittal };

std::optional<SliceAxis> find_slice_axis(std::string_view name);
const char* slice_axis_name(SliceAxis axis);

// A view's pixels in LPS world space, as radiologists read them: axial seen from the feet
// (patient left on the screen's right, anterior up), coronal from the front (left on the right,
// superior up), sagittal from the patient's left (anterior on the screen's left, superior up).
// Pixel (x, y)'s centre is at origin + (x + 0.5) * right + (y + 0.5) * down. With a slab, a
// pixel projects the samples along `normal` (unit) across the slab centred on it.
struct SliceView {
  SliceAxis axis = SliceAxis::axial;
  int width = 0, height = 0;
  glm::dvec3 origin{0.0}, right{0.0}, down{0.0}, normal{0.0};
  SlabProjection slab;

  glm::dvec3 world(double x, double y) const { return origin + x * right + y * down; }
  // The pixel coordinates (x, y, not rounded) of a world point's projection on the view.
  glm::dvec2 pixel(const glm::dvec3& p) const;
};

// The view of `axis` through `point` (the view's centre), `width` x `height` pixels of
// `mm_per_pixel` mm. An oblique view turns by `rotation` (a rotation of LPS): its normal is the
// axis's normal rotated, its down the axis's down made perpendicular to that normal (else the
// rotated down), so an oblique view keeps its up as near the patient's as it can (3D Slicer's
// and OHIF's reformatted views do the same).
SliceView slice_view(SliceAxis axis, const glm::dvec3& point, int width, int height,
                     double mm_per_pixel, const glm::dmat3& rotation = glm::dmat3(1.0));

std::optional<SlabMode> find_slab_mode(std::string_view name);
const char* slab_mode_name(SlabMode mode);

// The view's image (premultiplied linear RGBA, sRGB-encoded on output as a render): black where
// no volume is; the first volume in `shown` (indices into scene.volumes) in grey through
// windows[i]; each further one blended over it in its transfer function's colour, with the
// function's alpha relative to its largest as the weight (at most 0.7), or `overlay_weight`
// wherever it shows (figures: 1, opaque). NaN and inf voxels show nothing. Throws imx::Error for
// a view over 4096 pixels a side.
Image render_slice(const Scene& scene, const SliceView& view, const std::vector<int>& shown,
                   const std::vector<glm::dvec2>& windows,
                   std::optional<float> overlay_weight = std::nullopt);

// Where a mesh crosses the view's plane, as segments in the view's pixel coordinates
// [x0, y0, x1, y1], at most `max_segments` of them.
std::vector<glm::dvec4> mesh_outline(const Mesh& mesh, const SliceView& view,
                                     size_t max_segments = 20000);

// The value of a volume at a world point: the voxel whose cell holds it (nearest, as
// `intermix info`-level readers index it), or nullopt outside the grid.
struct VoxelValue {
  glm::ivec3 index;
  double value = 0.0;
};
std::optional<VoxelValue> voxel_at(const VolumeObject& volume, const glm::dvec3& point);

// The trilinear sample of a volume at a world point (as a view's pixel samples it, in double),
// or nullopt outside the grid's voxel extent; NaN where a no-data voxel takes part.
std::optional<double> sample_at(const VolumeObject& volume, const glm::dvec3& point);

}  // namespace imx
