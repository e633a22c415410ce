#include "figure/glass_projection.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <tbb/parallel_for.h>

#include "core/colour.hpp"
#include "volume/prepared_volume.hpp"

namespace imx {
namespace {

constexpr float kOutlineGrey = 0.35f;  // a display grey, as nilearn's outline

// A sample of a volume at a world point: NaN outside its grid (or where it has no data).
float sample_at(const PreparedVolume& v, const glm::vec3& world) {
  const glm::vec3 p = v.to_index(world);
  const glm::ivec3 dims = v.object->data->dims;
  if (!(p.x >= -0.5f && p.y >= -0.5f && p.z >= -0.5f && p.x <= dims.x - 0.5f &&
        p.y <= dims.y - 0.5f && p.z <= dims.z - 0.5f))
    return NAN;
  return v.grid.sample(glm::clamp(p, glm::vec3(0.0f), glm::vec3(dims - 1)));
}

// What one pixel's line through the box sees: the map's extreme and whether the anatomy shows.
struct LineOfSight {
  float extreme = NAN;
  bool subject = false;
};

LineOfSight look_along(const PreparedVolume& map, const PreparedVolume* anatomy, float background,
                       bool plot_abs, glm::vec3 start, glm::vec3 step, int steps) {
  LineOfSight seen;
  for (int n = 0; n <= steps; ++n) {
    const glm::vec3 p = start + step * static_cast<float>(n);
    float v = sample_at(map, p);
    if (std::isfinite(v)) {
      if (plot_abs) v = std::abs(v);
      if (!(seen.extreme >= v)) seen.extreme = v;  // NaN so far takes the first value
    }
    if (anatomy && !seen.subject) seen.subject = sample_at(*anatomy, p) > background;
  }
  return seen;
}

}  // namespace

Image glass_projection(const VolumeObject& map, const SliceView& view, const WorldBox& box,
                       bool plot_abs, const std::optional<GlassOutline>& outline) {
  const PreparedVolume prepared_map(map);
  std::optional<PreparedVolume> prepared_anatomy;
  if (outline) prepared_anatomy.emplace(*outline->anatomy);
  const float background = outline ? static_cast<float>(outline->background) : 0.0f;

  // Along the normal from the box's near face to its far face, the map's finest pitch apart.
  const glm::dvec3 n = glm::normalize(view.normal);
  const double near = glm::dot(n, box.lo), far = glm::dot(n, box.hi);
  const double pitch = prepared_map.min_pitch;
  const int steps = std::clamp(static_cast<int>(std::ceil((far - near) / pitch)), 1, 1 << 14);
  const glm::vec3 step(n * ((far - near) / steps));

  const int w = view.width, h = view.height;
  std::vector<uint8_t> subject(static_cast<size_t>(w) * h, 0);
  std::vector<float> extreme(static_cast<size_t>(w) * h, NAN);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const glm::dvec3 p = view.world(x + 0.5, y + 0.5);
      const glm::vec3 start(p + n * (near - glm::dot(n, p)));
      const LineOfSight seen =
          look_along(prepared_map, prepared_anatomy ? &*prepared_anatomy : nullptr, background,
                     plot_abs, start, step, steps);
      subject[static_cast<size_t>(y) * w + x] = seen.subject;
      extreme[static_cast<size_t>(y) * w + x] = seen.extreme;
    }
  });

  Image image(w, h, glm::vec4(1.0f));
  const glm::vec3 grey = display_to_linear(glm::vec3(kOutlineGrey));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = static_cast<size_t>(y) * w + x;
      glm::vec3 rgb(1.0f);
      // The outline: a subject pixel beside one that is not (or beside the panel's edge).
      const auto outside = [&](int xx, int yy) {
        return xx < 0 || yy < 0 || xx >= w || yy >= h || !subject[static_cast<size_t>(yy) * w + xx];
      };
      if (subject[i] &&
          (outside(x - 1, y) || outside(x + 1, y) || outside(x, y - 1) || outside(x, y + 1)))
        rgb = grey;
      if (std::isfinite(extreme[i])) {
        const glm::vec4 c = prepared_map.lut.lookup(extreme[i]);
        if (c.a > 0.0f) rgb = glm::vec3(c);  // opaque where it shows, as nilearn's
      }
      image.at(x, y) = glm::vec4(rgb, 1.0f);
    }
  return image;
}

}  // namespace imx
