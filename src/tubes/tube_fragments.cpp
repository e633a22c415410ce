#include "tubes/tube_fragments.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"
#include "presets/colormap.hpp"
#include "tubes/tube_cache.hpp"
#include "tubes/tube_coverage.hpp"

namespace imx {
namespace {

constexpr float kLetThrough = 1.0f / 1024.0f;
constexpr size_t kHitsPerQuery = 64;

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

// Sorts the fragments of `out` from `first` on by depth and drops those behind the one where
// what they let through, in depth order after `in_front`, falls below `bound`; returns what all
// the kept let through.
float cut_fragments(std::vector<Fragment>& out, size_t first, float bound, float in_front) {
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end(),
            [](const Fragment& a, const Fragment& b) { return a.t < b.t; });
  float through = in_front;
  for (size_t k = first; k < out.size(); ++k) {
    through *= 1.0f - out[k].color.a;
    if (through < bound) {
      out.resize(k + 1);
      break;
    }
  }
  return through;
}

}  // namespace

float tube_crossing_opacity(const TubeLook& look, uint32_t segment) {
  const StreamlineObject& o = *look.object;
  if (o.group_opacity.empty() || look.group_of.empty()) return o.opacity;
  const int32_t g = look.group_of[look.geometry->streamline(segment)];
  return g >= 0 && static_cast<size_t>(g) < o.group_opacity.size() ? o.group_opacity[g] : o.opacity;
}

float tube_fragment_alpha(float crossing_opacity) {
  return 1.0f - std::sqrt(1.0f - std::clamp(crossing_opacity, 0.0f, 1.0f));
}

glm::vec3 streamline_colour(const TubeLook& look, uint32_t streamline, uint32_t point, float u) {
  return colour_at(look, point, u, [&] { return streamline; });
}

TubeLook make_tube_look(const StreamlineObject& object, const TubeGeometry& geometry,
                        std::span<const MeshObject> meshes) {
  TubeLook look = make_tube_look(object);
  look.geometry = &geometry;
  if (!object.clip_planes.empty() && !geometry.is_connectome())
    look.clip = std::make_shared<const TubeClip>(object);
  if (!geometry.is_connectome()) look.clip_meshes = tube_clip_meshes(object, meshes);
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
  if (least_alpha >= 1.0f) return 1;
  if (least_alpha <= 0.0f) return SIZE_MAX;
  const double needed = std::ceil(std::log(kLetThrough) / std::log(1.0 - least_alpha));
  return static_cast<size_t>(std::clamp(needed, 1.0, 1e9));
}

void append_tube_fragments(const TubeLook& look, const Ray& ray, float t_max, uint32_t object,
                           std::span<const ShadingLight> lights, std::vector<Fragment>& out) {
  const glm::vec3 to_eye = -ray.dir;
  float let_through = 1.0f;
  // Whether a crossing behind those so far can still change a colour, or must be counted.
  auto more = [&] { return look.every_crossing || let_through >= kLetThrough; };
  // `coverage`: the part of the pixel a covered crossing covers; `facing` set for those only.
  auto emit = [&](const TubeHit& h, float coverage = 1.0f, int facing = -1) {
    Fragment f;
    f.t = h.t;
    f.object = object;
    f.front_facing = facing >= 0 ? static_cast<uint32_t>(facing)
                                 : (glm::dot(h.normal, ray.dir) < 0.0f ? 1u : 0u);
    const float alpha = tube_fragment_alpha(coverage * tube_crossing_opacity(look, h.segment));
    const glm::vec3 rgb =
        blinn_phong(look.object->shading, base_colour(look, h), h.normal, to_eye, lights);
    f.color = glm::vec4(rgb * alpha, alpha);
    out.push_back(f);
    let_through *= 1.0f - alpha;
  };
  // One end of a kept piece of the ray: set by a clip plane, a clip mesh, or neither.
  struct End {
    float t = 0.0f;
    int plane = -1;
    const TubeClipMeshes::End* mesh = nullptr;
  };
  // A cap where the ray meets a plane or a mesh at t inside a tube: flat, facing out of the kept
  // side.
  auto cap = [&](const End& e) {
    TubeHit h;
    if (e.plane < 0 && !(e.mesh && e.mesh->cut)) return;
    if (!look.geometry->contains(ray.at(e.t), &h)) return;  // the nearest segment's colour
    h.normal = e.plane >= 0 ? -look.clip->normal(e.plane) : e.mesh->normal;
    h.t = e.t;
    emit(h);
  };
  // Covered crossings, gathered from the padded tubes in one pass while the bound allows; a
  // gathering out of room goes on behind its farthest candidate, and the whole is then sorted
  // and cut at the bound in depth order.
  auto gather = [&](const End& lo, const End& hi) {
    const size_t first = out.size();
    const float before = let_through;
    float t_min = lo.t, in_front = let_through;
    bool resumed = false;
    for (;;) {
      CoveredGathering found(look, ray, lo.t, hi.t, t_min, in_front, kLetThrough);
      look.geometry->visit_hits(ray, found);
      for (const CoveredFragment& f : found.fragments())
        emit(TubeHit{f.t, f.normal, f.segment, f.u}, f.coverage, static_cast<int>(f.entry));
      if (!found.truncated()) break;
      t_min = found.resume_t();
      in_front = found.let_through_before(t_min);
      resumed = true;
    }
    if (resumed) let_through = cut_fragments(out, first, kLetThrough, before);
  };
  // The tubes between lo and hi, capped at both ends; false once what the fragments let
  // through is below the bound.
  auto draw = [&](const End& lo, const End& hi) {
    if (!(lo.t < hi.t)) return true;
    cap(lo);
    if (look.silhouette_aa) {
      gather(lo, hi);
      if (more()) cap(hi);
      return more();
    }
    std::array<TubeHit, kHitsPerQuery> buffer;
    // As many hits per query as the most transparent crossing needs to let through less than
    // the bound (up to 64): one for opaque tubes, the nearest alone being far cheaper to find.
    const std::span<TubeHit> hits(buffer.data(),
                                  look.every_crossing ? kHitsPerQuery : look.hits_per_query);
    float t_min = lo.t;
    while (more()) {
      const size_t n = look.geometry->nearest_hits(ray, t_min, hi.t, hits);
      for (size_t i = 0; i < n; ++i) emit(hits[i]);
      if (n < hits.size()) {
        if (more()) cap(hi);
        break;
      }
      t_min = hits[n - 1].t;
    }
    return more();
  };
  End lo{0.0f}, hi{t_max};
  if (look.clip) {
    const TubeClip::Span span = look.clip->kept(ray);
    lo = End{span.lo, span.lo_plane};
    if (span.hi < t_max) hi = End{span.hi, span.hi_plane};
  }
  if (!look.clip_meshes) {
    draw(lo, hi);
    return;
  }
  // Each piece the meshes keep, within what the planes keep: an end is the nearer cut's.
  TubeClipMeshes::Pieces pieces;
  look.clip_meshes->kept(ray, pieces);
  for (int p = 0; p < pieces.count; ++p) {
    const TubeClipMeshes::Piece& piece = pieces.piece[p];
    const End piece_lo = piece.lo.t > lo.t ? End{piece.lo.t, -1, &piece.lo} : lo;
    const End piece_hi = piece.hi.t < hi.t ? End{piece.hi.t, -1, &piece.hi} : hi;
    if (!draw(piece_lo, piece_hi)) return;
  }
}

}  // namespace imx
