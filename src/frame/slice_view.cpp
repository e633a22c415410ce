#include "frame/slice_view.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "core/colour.hpp"
#include "core/math.hpp"
#include "intermix/error.hpp"
#include "raster/shade_fragment.hpp"
#include "volume/classify.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/wide_scalar.hpp"

namespace imx {
namespace {

constexpr int kMaxSliceSide = 4096;
constexpr float kMaxOverlayWeight = 0.7f;

// One volume as a view samples it: its grid in index space, and how its value becomes colour.
struct SliceLayer {
  const PreparedVolume* volume;
  bool base;            // grey through the window, else the TF's colour over what is below
  float centre, width;  // the window
  float alpha_scale;    // 1 / the TF's largest alpha
  float fixed_weight;   // an overlay's weight wherever it shows; negative: by its opacity
  int samples;          // along the normal across the slab (1: the plane alone)
  glm::vec3 step;       // index-space step between the slab's samples
  SlabMode mode;
};

bool in_grid(const glm::vec3& p, const glm::ivec3& dims) {
  return p.x >= -0.5f && p.y >= -0.5f && p.z >= -0.5f && p.x <= dims.x - 0.5f &&
         p.y <= dims.y - 0.5f && p.z <= dims.z - 0.5f;
}

// The slab's value at a pixel whose plane sample is index point `p`: slab_along within the
// voxels' extent, as the thin view's; NaN when no sample lies there or holds data.
float slab_value(const SliceLayer& l, const glm::vec3& p, const glm::ivec3& dims) {
  float value = std::numeric_limits<float>::quiet_NaN();
  slab_along(l.volume->grid, p, l.step, l.samples, l.mode, glm::vec3(-0.5f), glm::vec3(dims) - 0.5f,
             l.volume->has_no_data, value);
  return value;
}

// How much of an overlay's colour covers what is below it.
float overlay_weight(const SliceLayer& l, float alpha) {
  if (l.fixed_weight >= 0.0f) return alpha > 0.0f ? l.fixed_weight : 0.0f;
  return std::min(kMaxOverlayWeight, alpha * l.alpha_scale * kMaxOverlayWeight);
}

// The colour of one pixel: pure, no allocation.
glm::vec4 slice_pixel(const std::vector<SliceLayer>& layers, const glm::vec3& world) {
  glm::vec3 rgb(0.0f);
  float covered = 0.0f;
  for (const SliceLayer& l : layers) {
    const glm::vec3 p = l.volume->to_index(world);
    const glm::ivec3 dims = l.volume->object->data->dims;
    const bool labels_or_colours = l.volume->labels.active() || l.volume->colours.active();
    // A slab shows wherever any of its samples lies in the grid; labels and colours the plane's.
    if (!in_grid(p, dims) && (l.samples == 1 || labels_or_colours)) continue;
    const glm::vec3 inside = glm::clamp(p, glm::vec3(0.0f), glm::vec3(dims - 1));
    if (l.volume->labels.active()) {  // a label map: its labels' colours, hidden ones nothing
      const glm::vec4 c = table_look(*l.volume, inside);
      const float shown = l.fixed_weight >= 0.0f ? l.fixed_weight : kMaxOverlayWeight;
      const float w = c.a > 0.0f ? (l.base ? 1.0f : shown) : 0.0f;
      rgb = rgb * (1.0f - w) + glm::vec3(c) * w;
      covered = std::max(covered, w);
      continue;
    }
    const float value = l.samples > 1 && !labels_or_colours ? slab_value(l, p, dims)
                                                            : l.volume->grid.sample(inside);
    if (!std::isfinite(value)) continue;
    if (l.volume->colours.active()) {  // a colour volume: its colours; over others, its opacity
      const glm::vec4 c = table_look(*l.volume, inside);
      const float w = l.base ? 1.0f : overlay_weight(l, c.a);
      rgb = rgb * (1.0f - w) + glm::vec3(c) * w;
      covered = std::max(covered, w);
      continue;
    }
    if (l.base) {
      // The window gives a display grey, as on an MPR plane's grey colour map.
      rgb = display_to_linear(glm::vec3(window_level(value, l.centre, l.width)));
      covered = 1.0f;
    } else {
      const glm::vec4 c = l.volume->lut.lookup(value);
      const float w = overlay_weight(l, c.a);
      rgb = rgb * (1.0f - w) + glm::vec3(c) * w;
      covered = std::max(covered, w);
    }
  }
  return {rgb, covered > 0.0f ? 1.0f : 0.0f};
}

}  // namespace

std::optional<SliceAxis> find_slice_axis(std::string_view name) {
  if (name == "axial") return SliceAxis::axial;
  if (name == "coronal") return SliceAxis::coronal;
  if (name == "sagittal") return SliceAxis::sagittal;
  return std::nullopt;
}

const char* slice_axis_name(SliceAxis axis) {
  return axis == SliceAxis::axial ? "axial" : axis == SliceAxis::coronal ? "coronal" : "sagittal";
}

std::optional<SlabMode> find_slab_mode(std::string_view name) {
  if (name == "mip") return SlabMode::mip;
  if (name == "minip") return SlabMode::minip;
  if (name == "mean") return SlabMode::mean;
  return std::nullopt;
}

const char* slab_mode_name(SlabMode mode) {
  return mode == SlabMode::mip ? "mip" : mode == SlabMode::minip ? "minip" : "mean";
}

glm::dvec2 SliceView::pixel(const glm::dvec3& p) const {
  const glm::dvec3 d = p - origin;
  return {glm::dot(d, right) / glm::dot(right, right), glm::dot(d, down) / glm::dot(down, down)};
}

SliceView slice_view(SliceAxis axis, const glm::dvec3& point, int width, int height,
                     double mm_per_pixel, const glm::dmat3& rotation) {
  SliceView v;
  v.axis = axis;
  v.width = width;
  v.height = height;
  // LPS: +x patient left, +y posterior, +z superior.
  glm::dvec3 right, down;
  if (axis == SliceAxis::axial) {
    right = {1, 0, 0}, down = {0, 1, 0}, v.normal = {0, 0, 1};
  } else if (axis == SliceAxis::coronal) {
    right = {1, 0, 0}, down = {0, 0, -1}, v.normal = {0, 1, 0};
  } else {
    right = {0, 1, 0}, down = {0, 0, -1}, v.normal = {1, 0, 0};
  }
  if (rotation != glm::dmat3(1.0)) {
    // Right keeps its side of down x normal (the sagittal view's frame is mirrored).
    const double hand = glm::dot(glm::cross(down, v.normal), right) > 0.0 ? 1.0 : -1.0;
    v.normal = glm::normalize(rotation * v.normal);
    glm::dvec3 d = down - glm::dot(down, v.normal) * v.normal;
    if (glm::length(d) < 1e-3) d = rotation * down;  // facing along down: down turns with it
    down = glm::normalize(d - glm::dot(d, v.normal) * v.normal);
    right = hand * glm::cross(down, v.normal);
  }
  v.right = right * mm_per_pixel;
  v.down = down * mm_per_pixel;
  v.origin = point - v.right * (0.5 * width) - v.down * (0.5 * height);
  return v;
}

Image render_slice(const Scene& scene, const SliceView& view, const std::vector<int>& shown,
                   const std::vector<glm::dvec2>& windows, std::optional<float> overlay_weight) {
  if (view.width < 1 || view.height < 1 || view.width > kMaxSliceSide ||
      view.height > kMaxSliceSide)
    throw Error(fmt::format("slice: {} x {} pixels; a view takes 1 to {} a side", view.width,
                            view.height, kMaxSliceSide));
  std::vector<PreparedVolume> prepared;
  prepared.reserve(shown.size());
  for (int i : shown) prepared.emplace_back(scene.volumes.at(static_cast<size_t>(i)));
  std::vector<SliceLayer> layers;
  for (size_t k = 0; k < prepared.size(); ++k) {
    const glm::dvec2 w = windows.at(static_cast<size_t>(shown[k]));
    const float top = prepared[k].lut.max_opacity();
    // Each volume samples the slab at its own pitch along the normal, in world space (tilted
    // grids are sampled where the slab is, not along their own axes).
    const glm::dvec3 normal = glm::normalize(view.normal);
    const SlabSampling sampling =
        slab_sampling(view.slab.thickness, pitch_along(prepared[k], normal));
    const glm::dvec3 step_world = normal * sampling.spacing;
    const glm::vec3 step =
        prepared[k].to_index(glm::vec3(step_world)) - prepared[k].to_index(glm::vec3(0.0f));
    layers.push_back({&prepared[k], k == 0, static_cast<float>(w.x), static_cast<float>(w.y),
                      top > 0.0f ? 1.0f / top : 0.0f, overlay_weight.value_or(-1.0f),
                      sampling.count, step, view.slab.mode});
  }
  Image image(view.width, view.height);
  const bool wide = wide_scalar_available();
  tbb::parallel_for(0, view.height, [&](int y) {
    run_wide_scalar(wide, [&] {
      for (int x = 0; x < view.width; ++x)
        image.at(x, y) = slice_pixel(layers, glm::vec3(view.world(x + 0.5, y + 0.5)));
    });
  });
  return image;
}

std::vector<glm::dvec4> mesh_outline(const Mesh& mesh, const SliceView& view, size_t max_segments) {
  const glm::dvec3 centre = view.world(0.5 * view.width, 0.5 * view.height);
  const double offset = glm::dot(view.normal, centre);
  std::vector<glm::dvec4> out;
  for (const glm::uvec3& t : mesh.triangles) {
    if (out.size() >= max_segments) break;
    const glm::dvec3 p[3] = {mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]};
    double d[3];
    for (int k = 0; k < 3; ++k) d[k] = glm::dot(view.normal, p[k]) - offset;
    glm::dvec3 hits[2];
    int n = 0;
    for (int k = 0; k < 3 && n < 2; ++k) {
      const int j = (k + 1) % 3;
      // An edge that crosses the plane (a vertex on it counts for the edge leaving it).
      if ((d[k] < 0.0) != (d[j] < 0.0)) hits[n++] = p[k] + (p[j] - p[k]) * (d[k] / (d[k] - d[j]));
    }
    if (n < 2) continue;
    const glm::dvec2 a = view.pixel(hits[0]), b = view.pixel(hits[1]);
    const auto off = [&](const glm::dvec2& q) {
      return q.x < 0 || q.y < 0 || q.x > view.width || q.y > view.height;
    };
    if (off(a) && off(b)) continue;
    out.push_back({a.x, a.y, b.x, b.y});
  }
  return out;
}

std::optional<VoxelValue> voxel_at(const VolumeObject& volume, const glm::dvec3& point) {
  const glm::dvec3 p = transform_point(glm::inverse(volume.index_to_world), point);
  const glm::ivec3 i(glm::round(p));
  const glm::ivec3 dims = volume.data->dims;
  if (glm::any(glm::lessThan(i, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(i, dims)))
    return std::nullopt;
  return VoxelValue{i, volume.data->value_at(i.x, i.y, i.z)};
}

std::optional<double> sample_at(const VolumeObject& volume, const glm::dvec3& point) {
  const glm::dvec3 p = transform_point(glm::inverse(volume.index_to_world), point);
  const glm::ivec3 dims = volume.data->dims;
  if (glm::any(glm::lessThan(p, glm::dvec3(-0.5))) ||
      glm::any(glm::greaterThan(p, glm::dvec3(dims) - 0.5)))
    return std::nullopt;
  const glm::dvec3 q = glm::clamp(p, glm::dvec3(0.0), glm::dvec3(dims - 1));
  const glm::ivec3 i0 = glm::min(glm::ivec3(glm::floor(q)), glm::max(dims - 2, glm::ivec3(0)));
  const glm::dvec3 f = q - glm::dvec3(i0);
  double sum = 0.0;
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 o((c & 1) ? 1 : 0, (c & 2) ? 1 : 0, (c & 4) ? 1 : 0);
    const glm::ivec3 i = glm::min(i0 + o, dims - 1);
    const double w = (o.x ? f.x : 1.0 - f.x) * (o.y ? f.y : 1.0 - f.y) * (o.z ? f.z : 1.0 - f.z);
    if (w == 0.0) continue;  // a no-data neighbour with no weight takes no part
    sum += w * volume.data->value_at(i.x, i.y, i.z);
  }
  return sum;
}

}  // namespace imx
