#include "server/streamline_slab.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include <tbb/parallel_for.h>
#include <glm/glm.hpp>

#include "tubes/tube_fragments.hpp"
#include "tubes/tube_selection.hpp"

namespace imx::server {
namespace {

// Clips the segment a + t (b - a), t in [t0, t1], to the box [lo, hi]^2 (Liang-Barsky); false
// when nothing is left.
bool clip_to_box(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& lo,
                 const glm::dvec2& hi, double& t0, double& t1) {
  const glm::dvec2 d = b - a;
  const double p[4] = {-d.x, d.x, -d.y, d.y};
  const double q[4] = {a.x - lo.x, hi.x - a.x, a.y - lo.y, hi.y - a.y};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0.0) {
      if (q[k] < 0.0) return false;
      continue;
    }
    const double t = q[k] / p[k];
    if (p[k] < 0.0)
      t0 = std::max(t0, t);
    else
      t1 = std::min(t1, t);
    if (t0 > t1) return false;
  }
  return true;
}

// `colour` (linear) over the pixel with `alpha`: premultiplied "over".
void blend(Image& image, int x, int y, const glm::vec3& colour, float alpha) {
  glm::vec4& px = image.at(x, y);
  px = glm::vec4(colour * alpha, alpha) + px * (1.0f - alpha);
}

// A line of `width` pixels from pixel coordinates a to b (both inside the image's box widened by
// the width), one square of width x width per step of at most a pixel.
void draw_line(Image& image, const glm::dvec2& a, const glm::dvec2& b, int width,
               const glm::vec3& colour, float alpha) {
  const double steps = std::ceil(std::max(std::abs(b.x - a.x), std::abs(b.y - a.y)));
  const int n = static_cast<int>(steps);
  int last_x = -1 << 30, last_y = -1 << 30;
  const double half = 0.5 * (width - 1);
  for (int i = 0; i <= n; ++i) {
    const glm::dvec2 p = n > 0 ? a + (b - a) * (static_cast<double>(i) / n) : a;
    const int x0 = static_cast<int>(std::floor(p.x - half)),
              y0 = static_cast<int>(std::floor(p.y - half));
    if (x0 == last_x && y0 == last_y) continue;  // one pixel once per step
    for (int y = std::max(y0, 0); y < std::min(y0 + width, image.height()); ++y)
      for (int x = std::max(x0, 0); x < std::min(x0 + width, image.width()); ++x)
        // Pixels the previous square covered stay as they are (no double blending at a joint).
        if (!(x >= last_x && x < last_x + width && y >= last_y && y < last_y + width))
          blend(image, x, y, colour, alpha);
    last_x = x0;
    last_y = y0;
  }
}

}  // namespace

size_t draw_streamline_slab(Image& image, const SliceView& view, const StreamlineObject& object,
                            double slab, int line_px, size_t max_segments) {
  if (!object.streamlines || !(object.opacity > 0.0f) || image.empty()) return 0;
  const Streamlines& s = *object.streamlines;
  const TubeLook look = make_tube_look(object);
  const glm::dvec3 normal = glm::normalize(view.normal);
  const double plane = glm::dot(normal, view.world(0.5 * view.width, 0.5 * view.height));
  const double half = 0.5 * slab;
  const int width = std::max(line_px, 1);
  const glm::dvec2 lo(-width, -width), hi(view.width + width, view.height + width);
  const float alpha = std::clamp(object.opacity, 0.0f, 1.0f);
  // The pieces within the slab, found in parallel per fixed chunk of streamlines and drawn in
  // the streamlines' order, so that the image does not depend on the threads.
  struct Piece {
    uint32_t streamline, point;
    double t0, t1;
  };
  const std::vector<uint32_t> selected = select_streamlines(object);
  constexpr size_t kChunk = 1024;
  std::vector<std::vector<Piece>> chunks((selected.size() + kChunk - 1) / kChunk);
  std::atomic<size_t> found{0};  // memory stays bounded by max_segments pieces and a chunk's
  tbb::parallel_for(size_t(0), chunks.size(), [&](size_t c) {
    const size_t end = std::min(selected.size(), (c + 1) * kChunk);
    for (size_t k = c * kChunk; k < end; ++k) {
      if (found.load(std::memory_order_relaxed) >= max_segments) break;
      const uint32_t i = selected[k];
      const uint32_t a = s.offsets[i], b = s.offsets[i + 1];
      double d1 = glm::dot(normal, glm::dvec3(s.points[a])) - plane;
      for (uint32_t p = a; p + 1 < b; ++p) {
        const double d0 = d1;
        d1 = glm::dot(normal, glm::dvec3(s.points[p + 1])) - plane;
        if ((d0 > half && d1 > half) || (d0 < -half && d1 < -half)) continue;  // most segments
        // The part of the segment within the slab: t in [t0, t1].
        double t0 = 0.0, t1 = 1.0;
        if (d0 != d1) {
          double ta = (-half - d0) / (d1 - d0), tb = (half - d0) / (d1 - d0);
          if (ta > tb) std::swap(ta, tb);
          t0 = std::max(t0, ta);
          t1 = std::min(t1, tb);
          if (t0 > t1) continue;
        }
        const glm::dvec2 q0 = view.pixel(glm::dvec3(s.points[p]));
        const glm::dvec2 q1 = view.pixel(glm::dvec3(s.points[p + 1]));
        if (clip_to_box(q0, q1, lo, hi, t0, t1)) chunks[c].push_back({i, p, t0, t1});
      }
    }
    found += chunks[c].size();
  });
  size_t drawn = 0;
  for (const std::vector<Piece>& chunk : chunks)
    for (const Piece& piece : chunk) {
      if (drawn >= max_segments) return drawn;
      ++drawn;
      const glm::dvec2 q0 = view.pixel(glm::dvec3(s.points[piece.point]));
      const glm::dvec2 q1 = view.pixel(glm::dvec3(s.points[piece.point + 1]));
      const float mid = static_cast<float>(0.5 * (piece.t0 + piece.t1));
      // Linear, as the slice it is drawn over (encoded when the view is written).
      const glm::vec3 colour =
          glm::clamp(streamline_colour(look, piece.streamline, piece.point, mid), 0.0f, 1.0f);
      draw_line(image, q0 + (q1 - q0) * piece.t0, q0 + (q1 - q0) * piece.t1, width, colour, alpha);
    }
  return drawn;
}

}  // namespace imx::server
