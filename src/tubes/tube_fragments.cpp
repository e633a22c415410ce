#include "tubes/tube_fragments.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"
#include "presets/colormap.hpp"
#include "tubes/tube_cache.hpp"

namespace imx {
namespace {

constexpr float kLetThrough = 1.0f / 1024.0f;
constexpr size_t kHitsPerQuery = 32;
constexpr int kNeighbourWalk = 16;  // segments a covered crossing looks along each way

const StreamlineValues* find_values(const std::vector<StreamlineValues>& all,
                                    const std::string& name) {
  for (const StreamlineValues& v : all)
    if (v.name == name) return &v;
  return nullptr;
}

std::string value_names(const std::vector<StreamlineValues>& all) {
  std::string names;
  for (const StreamlineValues& v : all) names += (names.empty() ? "'" : ", '") + v.name + "'";
  return names.empty() ? "none" : names;
}

// The colour at `u` along the segment from point `p` before lighting; `streamline()` gives the
// segment's streamline, asked only by the colourings that need it.
template <class StreamlineOf>
glm::vec3 colour_at(const TubeLook& look, uint32_t p, float u, StreamlineOf streamline) {
  const StreamlineObject& o = *look.object;
  const Streamlines& s = *o.streamlines;
  switch (o.colouring) {
    case StreamlineColouring::direction: {
      const glm::vec3 d = s.points[p + 1] - s.points[p];
      const float len = glm::length(d);
      return len > 0.0f ? glm::abs(d) / len : glm::vec3(0.0f);
    }
    case StreamlineColouring::streamline_direction: {
      const uint32_t i = streamline();
      const glm::vec3 d = s.points[s.offsets[i + 1] - 1] - s.points[s.offsets[i]];
      const float len = glm::length(d);
      return len > 0.0f ? glm::abs(d) / len : glm::vec3(0.0f);
    }
    case StreamlineColouring::fixed:
      return o.color;
    case StreamlineColouring::point_value:
    case StreamlineColouring::streamline_value: {
      const float v = look.point_values
                          ? look.point_values[p] * (1.0f - u) + look.point_values[p + 1] * u
                          : look.streamline_values[streamline()];
      const float span = look.value_high - look.value_low;
      const float x = span > 0.0f ? (v - look.value_low) / span : 0.5f;
      return colormap_rgb(o.colormap, std::clamp(x, 0.0f, 1.0f));
    }
    case StreamlineColouring::group: {
      const int32_t g = look.group_of[streamline()];
      return g >= 0 && s.groups[g].color ? *s.groups[g].color : o.color;
    }
  }
  return o.color;
}

// The colour of a crossing before lighting.
glm::vec3 base_colour(const TubeLook& look, const TubeHit& hit) {
  if (look.geometry->is_connectome()) return look.geometry->primitive_color(hit.segment);
  return colour_at(look, look.geometry->first_point(hit.segment), hit.u,
                   [&] { return look.geometry->streamline(hit.segment); });
}

float crossing_opacity(const TubeLook& look, const TubeHit& hit) {
  const StreamlineObject& o = *look.object;
  if (o.group_opacity.empty() || look.group_of.empty()) return o.opacity;
  const int32_t g = look.group_of[look.geometry->streamline(hit.segment)];
  return g >= 0 && static_cast<size_t>(g) < o.group_opacity.size() ? o.group_opacity[g] : o.opacity;
}

// Where a ray passes closest to a segment's axis.
struct Approach {
  float t = 0.0f;         // along the ray
  float u = 0.0f;         // along the segment, 0..1
  float distance = 0.0f;  // from the axis
  float sine = 1.0f;      // of the angle between the ray and the axis
};

Approach closest_approach(const Ray& ray, const glm::vec3& p0, const glm::vec3& p1) {
  const glm::vec3 e = p1 - p0, w = ray.origin - p0;
  const float b = glm::dot(ray.dir, e), d = glm::dot(ray.dir, w);
  const glm::vec3 e_perp = e - b * ray.dir, w_perp = w - d * ray.dir;
  const float ee = glm::dot(e_perp, e_perp), length2 = glm::dot(e, e);
  Approach a;
  a.u = ee > 1e-12f ? std::clamp(glm::dot(w_perp, e_perp) / ee, 0.0f, 1.0f) : 0.0f;
  a.t = a.u * b - d;
  a.distance = glm::length(w_perp - a.u * e_perp);
  a.sine = length2 > 0.0f ? std::sqrt(ee / length2) : 1.0f;
  return a;
}

// Where a ray enters and leaves a capsule: the union of a cylinder and two spheres, all convex,
// so from the first piece's entry to the last one's exit.
struct CapsuleSpan {
  bool hit = false;
  float t_in = INFINITY, t_out = -INFINITY;
};

CapsuleSpan capsule_span(const Ray& ray, const glm::vec3& pa, const glm::vec3& pb, float r) {
  CapsuleSpan span;
  auto take = [&](float t0, float t1) {
    span.hit = true;
    span.t_in = std::min(span.t_in, t0);
    span.t_out = std::max(span.t_out, t1);
  };
  for (const glm::vec3& centre : {pa, pb}) {
    const glm::vec3 oc = ray.origin - centre;
    const float b = glm::dot(ray.dir, oc), h = b * b - (glm::dot(oc, oc) - r * r);
    if (h >= 0.0f) take(-b - std::sqrt(h), -b + std::sqrt(h));
  }
  const glm::vec3 ba = pb - pa, oa = ray.origin - pa;
  const float baba = glm::dot(ba, ba), bard = glm::dot(ba, ray.dir), baoa = glm::dot(ba, oa);
  const float a = baba - bard * bard;
  if (a > 1e-12f * baba && baba > 0.0f) {
    const float b = baba * glm::dot(ray.dir, oa) - baoa * bard;
    const float c = baba * glm::dot(oa, oa) - baoa * baoa - r * r * baba;
    const float h = b * b - a * c;
    if (h >= 0.0f) {
      const float t0 = (-b - std::sqrt(h)) / a, t1 = (-b + std::sqrt(h)) / a;
      const float y0 = baoa + t0 * bard, y1 = baoa + t1 * bard;
      if (y0 > 0.0f && y0 < baba) take(t0, t0);
      if (y1 > 0.0f && y1 < baba) take(t1, t1);
    }
  }
  return span;
}

// The outward normal (not unit length) of the segment's tube at a point near its surface.
glm::vec3 radial(const glm::vec3& point, const glm::vec3& p0, const glm::vec3& p1) {
  const glm::vec3 e = p1 - p0;
  const float length2 = glm::dot(e, e);
  const float u = length2 > 0.0f ? std::clamp(glm::dot(point - p0, e) / length2, 0.0f, 1.0f) : 0.0f;
  return point - (p0 + u * e);
}

}  // namespace

float tube_coverage(float radius, float distance, float footprint) {
  if (!(footprint > 0.0f)) return distance <= radius ? 1.0f : 0.0f;
  return std::clamp((radius + 0.5f * footprint - distance) / footprint, 0.0f, 1.0f);
}

bool silhouette_aa_requested() {
  const char* v = std::getenv("IMX_TUBE_SILHOUETTE_AA");
  return v && v[0] == '1';
}

float silhouette_pad(float widest_footprint) {
  if (!(widest_footprint > 0.0f)) return 0.0f;
  return std::exp2(std::ceil(std::log2(0.5f * widest_footprint)));
}

void enable_silhouette_aa(TubeLook& look, float footprint_at_0, float footprint_per_mm) {
  if (!look.geometry || look.geometry->is_connectome()) return;
  look.silhouette_aa = true;
  look.footprint_at_0 = footprint_at_0;
  look.footprint_per_mm = footprint_per_mm;
  // Partly covering crossings let light through: an opaque object needs more than its nearest,
  // though rarely more than a few (each padded tube is an entry and an exit).
  look.hits_per_query = std::max<size_t>(look.hits_per_query, 6);
}

float tube_fragment_alpha(float crossing_opacity) {
  return 1.0f - std::sqrt(1.0f - std::clamp(crossing_opacity, 0.0f, 1.0f));
}

glm::vec3 streamline_colour(const TubeLook& look, uint32_t streamline, uint32_t point, float u) {
  return colour_at(look, point, u, [&] { return streamline; });
}

TubeLook make_tube_look(const StreamlineObject& object, const TubeGeometry& geometry) {
  TubeLook look = make_tube_look(object);
  look.geometry = &geometry;
  look.clip = tube_clip(object, geometry);
  return look;
}

TubeLook make_tube_look(const StreamlineObject& object) {
  TubeLook look;
  look.object = &object;
  const Streamlines& s = *object.streamlines;
  const bool per_point = object.colouring == StreamlineColouring::point_value;
  if (per_point || object.colouring == StreamlineColouring::streamline_value) {
    const auto& all = per_point ? s.point_values : s.streamline_values;
    const StreamlineValues* values = find_values(all, object.value);
    if (!values)
      throw Error(fmt::format("streamlines '{}': no per-{} values named '{}' (it has {})",
                              object.name, per_point ? "point" : "streamline", object.value,
                              value_names(all)));
    (per_point ? look.point_values : look.streamline_values) = values->values.data();
    if (object.range) {
      look.value_low = static_cast<float>(object.range->x);
      look.value_high = static_cast<float>(object.range->y);
    } else {
      auto [lo, hi] = std::minmax_element(values->values.begin(), values->values.end());
      if (lo != values->values.end()) look.value_low = *lo, look.value_high = *hi;
    }
  }
  if (!s.groups.empty() &&
      (object.colouring == StreamlineColouring::group || !object.group_opacity.empty())) {
    look.group_of.assign(s.count(), -1);
    for (size_t g = s.groups.size(); g-- > 0;)  // the first group wins
      for (uint32_t m : s.groups[g].members)
        if (m < look.group_of.size()) look.group_of[m] = static_cast<int32_t>(g);
  } else if (object.colouring == StreamlineColouring::group) {
    look.group_of.assign(s.count(), -1);
  }
  look.hits_per_query = std::min(tube_fragments_needed(object), kHitsPerQuery);
  return look;
}

size_t tube_fragments_needed(const StreamlineObject& object) {
  float least_alpha = tube_fragment_alpha(object.opacity);
  for (float g : object.group_opacity) least_alpha = std::min(least_alpha, tube_fragment_alpha(g));
  const size_t least = silhouette_aa_requested() && !object.connectome ? kCoveredFragments : 1;
  if (least_alpha >= 1.0f) return least;
  if (least_alpha <= 0.0f) return SIZE_MAX;
  const double needed = std::ceil(std::log(kLetThrough) / std::log(1.0 - least_alpha));
  return std::max(static_cast<size_t>(std::clamp(needed, 1.0, 1e9)), least);
}

namespace {

void append_in_query_order(const TubeLook& look, const Ray& ray, float t_max, uint32_t object,
                           std::span<const ShadingLight> lights, std::vector<Fragment>& out) {
  std::array<TubeHit, kHitsPerQuery> buffer;
  // As many hits per query as the most transparent crossing needs to let through less than the
  // bound: one for opaque tubes, the nearest alone being far cheaper to find than 32.
  const std::span<TubeHit> hits(buffer.data(), look.hits_per_query);
  const glm::vec3 to_eye = -ray.dir;
  float let_through = 1.0f, t_min = 0.0f, farthest = 0.0f;
  auto emit = [&](const TubeHit& h, float coverage = 1.0f, int facing = -1) {
    Fragment f;
    f.t = h.t;
    f.object = object;
    f.front_facing = facing >= 0 ? static_cast<uint32_t>(facing)
                                 : (glm::dot(h.normal, ray.dir) < 0.0f ? 1u : 0u);
    const float alpha = tube_fragment_alpha(coverage * crossing_opacity(look, h));
    if (look.shaded) {
      const glm::vec3 rgb =
          blinn_phong(look.object->shading, base_colour(look, h), h.normal, to_eye, lights);
      f.color = glm::vec4(rgb * alpha, alpha);
    }
    out.push_back(f);
    let_through *= 1.0f - alpha;
    farthest = std::max(farthest, h.t);
  };
  // A cap where the ray meets `plane` at t inside a tube: flat, facing out of the kept side.
  auto cap = [&](int plane, float t) {
    TubeHit h;
    if (plane < 0 || !look.clip->inside(plane, ray.at(t), &h)) return;
    h.t = t;
    h.normal = -look.clip->normal(plane);
    emit(h);
  };
  // With silhouette coverage the Embree tubes are padded: each entry into one is a candidate
  // crossing, measured against the true radius at the segment's closest approach.
  auto covered_crossing = [&](const TubeHit& candidate) {
    if (glm::dot(candidate.normal, ray.dir) >= 0.0f) return;  // the padded tube's exit
    const std::vector<glm::vec3>& points = look.object->streamlines->points;
    const TubeGeometry& g = *look.geometry;
    const float radius = g.radius(), reach = radius + g.pad();
    // Joined segments share one padded surface: the ray may pass nearest to a neighbour of the
    // segment it entered by, so look along the streamline while its segments stay within reach.
    // The round tube is the union of its segments' capsules: it spans from the first capsule
    // entry to the last exit.
    uint32_t best = candidate.segment;
    Approach a =
        closest_approach(ray, points[g.first_point(best)], points[g.first_point(best) + 1]);
    float t_in = INFINITY, t_out = -INFINITY;
    uint32_t seg_in = best, seg_out = best;
    auto span_of = [&](uint32_t segment) {
      const uint32_t q = g.first_point(segment);
      const CapsuleSpan c = capsule_span(ray, points[q], points[q + 1], radius);
      if (!c.hit) return;
      if (c.t_in < t_in) t_in = c.t_in, seg_in = segment;
      if (c.t_out > t_out) t_out = c.t_out, seg_out = segment;
    };
    span_of(best);
    for (const int step : {1, -1}) {
      uint32_t segment = candidate.segment;
      for (int k = 0; k < kNeighbourWalk; ++k) {
        const int64_t next = static_cast<int64_t>(segment) + step;
        if (next < 0 || static_cast<size_t>(next) >= g.segment_count()) break;
        const uint32_t q = g.first_point(static_cast<uint32_t>(next));
        if (q != g.first_point(segment) + step) break;  // another streamline
        const Approach b = closest_approach(ray, points[q], points[q + 1]);
        if (!(b.distance < reach)) break;
        segment = static_cast<uint32_t>(next);
        span_of(segment);
        if (b.distance < a.distance) a = b, best = segment;
      }
    }
    const float footprint = look.footprint_at_0 + look.footprint_per_mm * std::max(a.t, 0.0f);
    const float coverage = tube_coverage(radius, a.distance, footprint);
    if (!(coverage > 0.0f)) return;
    // Through the tube: its entry and exit; past it: both at the closest approach.
    if (!(t_in <= t_out)) t_in = t_out = a.t, seg_in = seg_out = best;
    TubeHit h;
    h.segment = best;
    h.u = a.u;
    for (int entry = 1; entry >= 0; --entry) {
      const uint32_t segment = entry ? seg_in : seg_out;
      const uint32_t q = g.first_point(segment);
      h.t = entry ? t_in : t_out;
      h.normal = radial(ray.at(h.t), points[q], points[q + 1]);
      emit(h, coverage, entry);
    }
  };
  TubeClip::Span span{0.0f, t_max, -1, -1};
  if (look.clip) {
    span = look.clip->kept(ray);
    if (span.hi >= t_max) span.hi = t_max, span.hi_plane = -1;
    if (!(span.lo < span.hi)) return;
    cap(span.lo_plane, span.lo);
    t_min = span.lo;
    t_max = span.hi;
  }
  // Covered crossings come in the order of their padded entries, not their own: once the bound
  // is reached, a crossing whose padded entry lies before the farthest fragment drawn can still
  // be in front of it, so those are still asked for.
  while (let_through >= kLetThrough || (look.silhouette_aa && t_min < t_max)) {
    if (look.silhouette_aa && let_through < kLetThrough) t_max = std::min(t_max, farthest);
    const size_t n = look.geometry->nearest_hits(ray, t_min, t_max, hits);
    for (size_t i = 0; i < n; ++i) {
      if (look.silhouette_aa)
        covered_crossing(hits[i]);
      else
        emit(hits[i]);
    }
    if (n < hits.size()) {
      if (look.clip && let_through >= kLetThrough) cap(span.hi_plane, span.hi);
      return;
    }
    t_min = hits[n - 1].t;
  }
}

}  // namespace

void append_tube_fragments(const TubeLook& look, const Ray& ray, float t_max, uint32_t object,
                           std::span<const ShadingLight> lights, std::vector<Fragment>& out) {
  const size_t first = out.size();
  append_in_query_order(look, ray, t_max, object, lights, out);
  // Covered crossings are found by their padded entries: nearest first as the methods expect.
  if (look.silhouette_aa)
    std::stable_sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end(),
                     [](const Fragment& a, const Fragment& b) { return a.t < b.t; });
}

}  // namespace imx
