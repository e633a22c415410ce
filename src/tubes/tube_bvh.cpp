#include "tubes/tube_bvh.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <glm/glm.hpp>
#include "tubes/capsule.hpp"
#include "tubes/tube_bvh_builder.hpp"

namespace imx {
namespace {

constexpr int kStackDepth = kTubeBvhMaxDepth;

using Box = TubeBox;
using Item = TubeBvhItem;

float segment_radius(const TubeBvh::Input& in, uint32_t segment) {
  return in.radii.empty() ? in.radius : in.radii[segment];
}

bool joined(const TubeBvh::Input& in, size_t a, size_t b) {
  return in.segment_points[b] == in.segment_points[a] + 1;
}

glm::vec3 unit(const glm::vec3& v) {
  const float length = glm::length(v);
  return length > 0.0f ? v / length : glm::vec3(0.0f);
}

// Eight segments at once: those of `run` whose infinite cylinder the ray meets within the reach
// (a superset of the capsules it crosses), as bits. Lanes past the run's end stay clear.
uint32_t run_candidates(const TubeBvh::Input& input, const TubeBvh::Run& run, const glm::vec3* p,
                        const Ray& ray, float lowest, float reach) {
  constexpr int kRunSegments = TubeBvh::kRunSegments;
  using f8 = float __attribute__((vector_size(32)));
  using i8 = int32_t __attribute__((vector_size(32)));
  f8 ax, ay, az, bx, by, bz, rr;
  for (int j = 0; j < kRunSegments; ++j) {
    const int k = j < run.segments ? j : run.segments - 1;  // past the end: repeats, masked
    ax[j] = p[k].x, ay[j] = p[k].y, az[j] = p[k].z;
    bx[j] = p[k + 1].x, by[j] = p[k + 1].y, bz[j] = p[k + 1].z;
  }
  if (input.radii.empty()) {
    rr = f8{} + input.radius * input.radius;
  } else {
    for (int j = 0; j < kRunSegments; ++j) {
      const float r = input.radii[run.first_segment + std::min<int>(j, run.segments - 1)];
      rr[j] = r * r;
    }
  }
  const float dx = ray.dir.x, dy = ray.dir.y, dz = ray.dir.z;
  const f8 wx = ray.origin.x - ax, wy = ray.origin.y - ay, wz = ray.origin.z - az;
  const f8 shift = -(wx * dx + wy * dy + wz * dz);
  const f8 ox = wx + shift * dx, oy = wy + shift * dy, oz = wz + shift * dz;
  const f8 ux = bx - ax, uy = by - ay, uz = bz - az;
  const f8 baba = ux * ux + uy * uy + uz * uz, bard = ux * dx + uy * dy + uz * dz;
  // The ray's line against the capsule: the segment's point nearest the line, in the plane
  // across the ray (where `a` lies at -o and the segment runs along pb), within the radius.
  const f8 pbx = ux - bard * dx, pby = uy - bard * dy, pbz = uz - bard * dz;
  const f8 pbpb = pbx * pbx + pby * pby + pbz * pbz;
  f8 s = (ox * pbx + oy * pby + oz * pbz) / pbpb;
  s = pbpb > 0.0f ? s : 0.0f;
  s = s > 0.0f ? s : 0.0f;
  s = s < 1.0f ? s : 1.0f;
  const f8 nx = s * pbx - ox, ny = s * pby - oy, nz = s * pbz - oz;
  const i8 meets = nx * nx + ny * ny + nz * nz <= rr * 1.0001f;
  // Crossings lie within |ba| + r of where the ray passes `a`; (|ba| + r)^2 <= 2 (|ba|^2 + r^2).
  const f8 extent2 = 2.0f * (baba + rr);
  const f8 before = lowest - shift, after = shift - reach;
  const i8 in_reach =
      (before <= 0.0f || before * before < extent2) & (after <= 0.0f || after * after < extent2);
  const i8 keep = meets & in_reach;
  uint32_t bits = 0;
  for (int j = 0; j < kRunSegments; ++j) bits |= static_cast<uint32_t>(keep[j] & 1) << j;
  return bits & ((1u << run.segments) - 1);
}

}  // namespace

TubeBvh::TubeBvh(const Input& input) : input_(input) {
  static_assert(sizeof(Run) == sizeof(glm::vec3));
  const size_t segments = input.segment_points.size();
  if (segments == 0) return;
  // Runs of joined segments, at most kRunSegments long.
  std::vector<Run> runs;
  for (size_t k = 0; k < segments;) {
    size_t end = k + 1;
    while (end < segments && end - k < kRunSegments && joined(input, end - 1, end)) ++end;
    Run run{static_cast<uint32_t>(k), static_cast<uint16_t>(end - k), 0};
    if (k > 0 && joined(input, k - 1, k)) run.joins |= 1;
    if (end < segments && joined(input, end - 1, end)) run.joins |= 2;
    runs.push_back(run);
    k = end;
  }
  std::vector<Item> items(runs.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, runs.size(), 4096), [&](const auto& range) {
    for (size_t i = range.begin(); i < range.end(); ++i) {
      const Run& run = runs[i];
      Box b = Box::empty();
      float r = 0.0f;
      for (uint32_t s = run.first_segment; s < run.first_segment + run.segments; ++s)
        r = std::max(r, segment_radius(input_, s));
      const uint32_t p = input_.segment_points[run.first_segment];
      for (uint32_t q = p; q <= p + run.segments; ++q) b.grow(input_.points[q]);
      // Padded beyond the radius by float rounding of the coordinates, so no grazing hit is lost.
      const glm::vec3 pad =
          glm::vec3(r) + 1e-5f + 1e-6f * glm::max(glm::abs(b.low), glm::abs(b.high));
      b.low -= pad, b.high += pad;
      items[i] = Item{b, static_cast<uint32_t>(i)};
    }
  });
  Box all = Box::empty();
  for (const Item& item : items) all.grow(item.box);
  // The binary tree, collapsed into 8-wide nodes, each freed before the next stage grows.
  std::vector<uint32_t> at(runs.size() + 1, 0);  // run i of the tree's order: stream offset
  {
    std::vector<Node> binary = build_tube_tree(items, all);
    for (size_t i = 0; i < items.size(); ++i)
      at[i + 1] = at[i] + runs[items[i].run].segments + kRunExtra;
    if (at.back() >= kMaxStream) throw std::length_error("tubes: more than 2^29 leaf points");
    for (Node& n : binary)
      if (n.count > 0) n.first = at[n.first];
    nodes_.reserve(binary.size() / 4 + 1);
    if (binary[0].count > 0) {  // one leaf: the only child of the root
      nodes_.emplace_back();
      for (int i = 0; i < 8; ++i) set_child(nodes_[0], i, i == 0 ? &binary[0] : nullptr, 0);
    } else {
      collapse(binary, 0);
    }
  }
  // The runs in the tree's order, copied with their points into the leaf stream.
  stream_.resize(at.back());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, runs.size(), 4096), [&](const auto& range) {
    for (size_t i = range.begin(); i < range.end(); ++i) {
      Run run = runs[items[i].run];
      const uint32_t p = input_.segment_points[run.first_segment], n = run.segments;
      float r = 0.0f, off = 0.0f;
      for (uint32_t s = run.first_segment; s < run.first_segment + n; ++s)
        r = std::max(r, segment_radius(input_, s));
      for (uint32_t k = 0; k <= n; ++k)
        off = std::max(off, std::sqrt(distance2_to_segment(input_.points[p + k], input_.points[p],
                                                           input_.points[p + n])));
      run.bound = (r + off) * 1.0001f + 1e-5f;
      glm::vec3* out = stream_.data() + at[i];
      std::memcpy(static_cast<void*>(&out[0]), &run, sizeof(Run));
      out[1] = input_.points[run.joins & 1 ? p - 1 : p];
      for (uint32_t k = 0; k <= n; ++k) out[2 + k] = input_.points[p + k];
      out[n + 3] = input_.points[run.joins & 2 ? p + n + 1 : p + n];
    }
  });
  nodes_.shrink_to_fit();
}

// Child i of `w`: none (n null), the leaf `n`, or the wide node `inner` made from `n`.
void TubeBvh::set_child(WideNode& w, int i, const Node* n, uint32_t inner) {
  if (!n) {
    for (int a = 0; a < 3; ++a) w.low[a][i] = 1.0f, w.high[a][i] = -1.0f;
    w.child[i] = kNoChild;
    return;
  }
  for (int a = 0; a < 3; ++a) w.low[a][i] = n->low[a], w.high[a][i] = n->high[a];
  w.child[i] = n->count > 0 ? kLeafChild | (n->count - 1) << 29 | n->first : inner;
}

// The wide node under binary node `node` (inner): its children opened, largest box first,
// until eight are inner nodes' and leaves.
uint32_t TubeBvh::collapse(const std::vector<Node>& binary, uint32_t node) {
  std::array<uint32_t, 8> kids{};
  int count = 2;
  kids[0] = binary[node].first, kids[1] = binary[node].first + 1;
  auto area = [&](uint32_t k) {
    const Node& n = binary[k];
    const float x = n.high[0] - n.low[0], y = n.high[1] - n.low[1], z = n.high[2] - n.low[2];
    return x * y + y * z + z * x;
  };
  while (count < 8) {
    int open = -1;
    for (int i = 0; i < count; ++i)
      if (binary[kids[i]].count == 0 && (open < 0 || area(kids[i]) > area(kids[open]))) open = i;
    if (open < 0) break;
    const uint32_t first = binary[kids[open]].first;
    kids[open] = first;
    kids[count++] = first + 1;
  }
  const uint32_t index = static_cast<uint32_t>(nodes_.size());
  nodes_.emplace_back();
  for (int i = 0; i < 8; ++i) {
    const Node* n = i < count ? &binary[kids[i]] : nullptr;
    const uint32_t inner = n && n->count == 0 ? collapse(binary, kids[i]) : 0;
    set_child(nodes_[index], i, n, inner);  // after collapsing: nodes_ may have moved
  }
  return index;
}

size_t TubeBvh::bytes() const {
  return nodes_.capacity() * sizeof(WideNode) + stream_.capacity() * sizeof(glm::vec3);
}

template <class Sink>
uint32_t TubeBvh::hit_run(const glm::vec3* stream, const Ray& ray, Sink& list) const {
  Run run;
  std::memcpy(static_cast<void*>(&run), stream, sizeof(Run));
  const glm::vec3* p = stream + 2;
  const float t_min = list.t_min;
  if (!line_meets_capsule(ray, p[0], p[run.segments], run.bound)) return run.segments + kRunExtra;
  for (uint32_t bits = run_candidates(input_, run, p, ray, std::max(t_min, 0.0f), list.reach());
       bits != 0; bits &= bits - 1) {
    const int j = __builtin_ctz(bits);
    const uint32_t segment = run.first_segment + j;
    const float r = segment_radius(input_, segment);
    const glm::vec3 a = p[j];
    // The origin moved to the ray's point nearest `a`, so the quadratic sees small numbers.
    const glm::vec3 w = ray.origin - a;
    const float shift = -glm::dot(w, ray.dir);
    const glm::vec3 o = w + shift * ray.dir;
    const glm::vec3 ba = p[j + 1] - a;
    const CapsuleCrossings c = capsule_crossings(o, ray.dir, ba, r);
    const bool has_left = j > 0 || (run.joins & 1);
    const bool has_right = j + 1 < run.segments || (run.joins & 2);
    const float baba = glm::dot(ba, ba);
    // Joined segments split their capsules at the plane bisecting the joint: with equal
    // radii the two surfaces meet there, so each crossing of the tube is reported once. The
    // planes' normals are sums of unit directions, the same sums for both neighbours.
    glm::vec3 left(0.0f), right(0.0f);
    bool planes = false;
    for (int k = 0; k < c.count; ++k) {
      const float t = shift + c.t[k];
      if (!(t > t_min) || !(t < list.reach())) continue;
      if (!planes && (has_left || has_right)) {
        const glm::vec3 e = unit(ba);
        if (has_left) left = e + unit(a - p[j - 1]);
        if (has_right) right = e + unit(p[j + 2] - p[j + 1]);
        planes = true;
      }
      const glm::vec3 x = o + c.t[k] * ray.dir;
      if (glm::dot(x, left) < 0.0f || (has_right && glm::dot(x - ba, right) >= 0.0f)) continue;
      const float along = glm::dot(x, ba);
      const float u = baba > 0.0f ? std::clamp(along / baba, 0.0f, 1.0f) : 0.0f;
      list.add(TubeHit{t, x - u * ba, segment, u},
               TubeRunPoints{p, run.first_segment, run.segments, run.joins});
    }
  }
  return run.segments + kRunExtra;
}

size_t TubeBvh::nearest_hits(const Ray& ray, float t_min, float t_max,
                             std::span<TubeHit> out) const {
  if (out.empty() || nodes_.empty()) return 0;
  TubeHitList list{out.data(), out.size(), 0, t_min, t_max};
  traverse(ray, list);
  return list.count;
}

void TubeBvh::visit_hits(const Ray& ray, TubeHitVisitor& visitor) const {
  // The visitor's own bounds, as a TubeHitList keeps them.
  struct Sink {
    TubeHitVisitor& visitor;
    float t_min;
    float reach() const { return visitor.reach; }
    void add(const TubeHit& hit, const TubeRunPoints& run) {
      if (hit.t > t_min && hit.t < visitor.reach) visitor.add(hit, run);
    }
  } sink{visitor, visitor.t_min};
  if (!nodes_.empty()) traverse(ray, sink);
}

template <class Sink>
void TubeBvh::traverse(const Ray& ray, Sink& list) const {
  using f8 = float __attribute__((vector_size(32)));
  using i8 = int32_t __attribute__((vector_size(32)));
  const float lowest = std::max(list.t_min, 0.0f);
  float inv[3];
  for (int a = 0; a < 3; ++a)
    inv[a] = std::abs(ray.dir[a]) > 1e-20f ? 1.0f / ray.dir[a] : std::copysign(1e20f, ray.dir[a]);
  struct Pending {
    uint32_t child;
    float t;
  };
  std::array<Pending, kStackDepth * 8> stack;
  int top = 0;
  stack[top++] = {0, lowest};
  while (top > 0) {
    const Pending p = stack[--top];
    if (p.t > list.reach()) continue;
    if (p.child & kLeafChild) {
      const glm::vec3* run = stream_.data() + (p.child & (kMaxStream - 1));
      const uint32_t runs = ((p.child >> 29) & 3) + 1;
      for (uint32_t i = 0; i < runs; ++i) run += hit_run(run, ray, list);
      continue;
    }
    const WideNode& n = nodes_[p.child];
    f8 lo = f8{} + lowest, hi = f8{} + list.reach();
    for (int a = 0; a < 3; ++a) {
      f8 low, high;
      std::memcpy(&low, n.low[a], sizeof(f8));
      std::memcpy(&high, n.high[a], sizeof(f8));
      const f8 t0 = (low - ray.origin[a]) * inv[a], t1 = (high - ray.origin[a]) * inv[a];
      lo = lo > (t0 < t1 ? t0 : t1) ? lo : (t0 < t1 ? t0 : t1);
      hi = hi < (t0 > t1 ? t0 : t1) ? hi : (t0 > t1 ? t0 : t1);
    }
    const i8 entered = lo <= hi;
    // The children entered, nearest pushed last so that it is visited first.
    Pending near[8];
    int found = 0;
    for (int i = 0; i < 8; ++i) {
      if (!entered[i] || n.child[i] == kNoChild) continue;
      const Pending c{n.child[i], lo[i]};
      if (c.child & kLeafChild) __builtin_prefetch(stream_.data() + (c.child & (kMaxStream - 1)));
      int k = found++;
      for (; k > 0 && near[k - 1].t < c.t; --k) near[k] = near[k - 1];
      near[k] = c;
    }
    for (int i = 0; i < found; ++i) stack[top++] = near[i];
  }
}

bool TubeBvh::contains(const glm::vec3& point, TubeHit* where) const {
  if (nodes_.empty()) return false;
  TubeHit nearest;
  float nearest2 = std::numeric_limits<float>::infinity();
  std::array<uint32_t, kStackDepth * 8> stack;
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const uint32_t child = stack[--top];
    if (!(child & kLeafChild)) {
      const WideNode& n = nodes_[child];
      for (int i = 0; i < 8; ++i) {
        bool inside = n.child[i] != kNoChild;
        for (int a = 0; a < 3; ++a)
          inside = inside && point[a] >= n.low[a][i] && point[a] <= n.high[a][i];
        if (inside) stack[top++] = n.child[i];
      }
      continue;
    }
    const glm::vec3* stream = stream_.data() + (child & (kMaxStream - 1));
    const uint32_t runs = ((child >> 29) & 3) + 1;
    for (uint32_t i = 0; i < runs; ++i, stream += kRunExtra) {
      Run run;
      std::memcpy(static_cast<void*>(&run), stream, sizeof(Run));
      const glm::vec3* p = stream + 2;
      stream += run.segments;
      for (uint32_t j = 0; j < run.segments; ++j) {
        const uint32_t segment = run.first_segment + j;
        const glm::vec3 a = p[j], ba = p[j + 1] - a;
        const glm::vec3 xa = point - a;
        const float len2 = glm::dot(ba, ba);
        const float u = len2 > 0.0f ? std::clamp(glm::dot(xa, ba) / len2, 0.0f, 1.0f) : 0.0f;
        const glm::vec3 off = xa - u * ba;
        const float r = segment_radius(input_, segment);
        const float d2 = glm::dot(off, off);
        if (d2 <= r * r && d2 < nearest2) nearest = TubeHit{0.0f, off, segment, u}, nearest2 = d2;
      }
    }
  }
  if (nearest2 == std::numeric_limits<float>::infinity()) return false;
  if (where) *where = nearest;
  return true;
}

}  // namespace imx
