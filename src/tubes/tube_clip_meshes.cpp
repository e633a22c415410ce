#include "tubes/tube_clip_meshes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "frame/clip_intervals.hpp"
#include "intermix/error.hpp"
#include "intermix/limits.hpp"

namespace imx {
namespace {

// Mesh slot k is its own winding number k (ClipView's object-to-slot map, the identity).
constexpr std::array<int8_t, kMaxClipMeshes> kIdentitySlots = [] {
  std::array<int8_t, kMaxClipMeshes> a{};
  for (int k = 0; k < kMaxClipMeshes; ++k) a[k] = static_cast<int8_t>(k);
  return a;
}();

constexpr uint32_t kLeafTriangles = 4;
constexpr int kStackDepth = 64;  // a median split of 2^32 triangles is 31 levels deep

// Every crossing of one ray with the meshes, sorted by t, with each one's outward normal.
struct Crossings {
  std::array<Fragment, TubeClipMeshes::kMaxCrossings> row;  // t, object = mesh, front_facing
  std::array<glm::vec3, TubeClipMeshes::kMaxCrossings> outward;
  int count = 0;
  bool overflow = false;

  void add(float t, uint32_t mesh, const glm::vec3& n, const glm::vec3& dir) {
    const uint32_t entering = glm::dot(n, dir) < 0.0f ? 1u : 0u;
    // A ray through an edge or vertex shared by triangles meets each of them: one crossing.
    for (int i = 0; i < count; ++i)
      if (row[i].object == mesh && row[i].front_facing == entering &&
          std::abs(row[i].t - t) <= 1e-5f * std::max(1.0f, t))
        return;
    if (count == TubeClipMeshes::kMaxCrossings) {
      overflow = true;
      return;
    }
    int i = count++;
    for (; i > 0 && row[i - 1].t > t; --i) {
      row[i] = row[i - 1];
      outward[i] = outward[i - 1];
    }
    row[i] = Fragment{t, glm::vec4(0.0f), mesh, entering};
    outward[i] = n;
  }
};

// The end of a piece at `t`: the crossing there, its normal turned toward `facing`.
TubeClipMeshes::End end_at(float t, const Crossings& all, const glm::vec3& facing) {
  TubeClipMeshes::End e;
  e.t = t;
  if (!std::isfinite(t)) return e;
  for (int i = 0; i < all.count; ++i)
    if (all.row[i].t == t) {
      e.cut = true;
      const glm::vec3 n = all.outward[i];
      e.normal = glm::dot(n, facing) >= 0.0f ? n : -n;
      break;
    }
  return e;
}

}  // namespace

// The meshes' triangles in a bounding volume hierarchy: median splits on the longest axis of
// the centroids, leaves of up to kLeafTriangles, a node's two children side by side.
struct TubeClipMeshes::Bvh {
  struct Triangle {
    glm::vec3 a, b, c;
    glm::vec3 outward;  // unit: the meshes are wound outward
    uint32_t mesh;
  };
  struct Node {
    glm::vec3 lo, hi;
    uint32_t first = 0;  // a leaf's first triangle, an inner node's first child
    uint32_t count = 0;  // a leaf's triangles; 0 for an inner node
  };
  std::vector<Triangle> triangles;
  std::vector<Node> nodes;

  void build(uint32_t node, std::vector<uint32_t>& order, uint32_t begin, uint32_t end,
             const std::vector<Triangle>& all) {
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    glm::vec3 c_lo = lo, c_hi = hi;
    for (uint32_t i = begin; i < end; ++i) {
      const Triangle& t = all[order[i]];
      lo = glm::min(lo, glm::min(t.a, glm::min(t.b, t.c)));
      hi = glm::max(hi, glm::max(t.a, glm::max(t.b, t.c)));
      const glm::vec3 centre = (t.a + t.b + t.c) / 3.0f;
      c_lo = glm::min(c_lo, centre);
      c_hi = glm::max(c_hi, centre);
    }
    nodes[node].lo = lo;
    nodes[node].hi = hi;
    const glm::vec3 extent = c_hi - c_lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                     : extent.y >= extent.z                       ? 1
                                                                  : 2;
    if (end - begin <= kLeafTriangles || !(extent[axis] > 0.0f)) {
      nodes[node].first = begin;
      nodes[node].count = end - begin;
      return;
    }
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                     [&](uint32_t x, uint32_t y) {
                       const Triangle &p = all[x], &q = all[y];
                       return p.a[axis] + p.b[axis] + p.c[axis] < q.a[axis] + q.b[axis] + q.c[axis];
                     });
    const uint32_t left = static_cast<uint32_t>(nodes.size());
    nodes.resize(nodes.size() + 2);
    nodes[node].first = left;
    nodes[node].count = 0;
    build(left, order, begin, mid, all);
    build(left + 1, order, mid, end, all);
  }

  // Every crossing of the ray with t >= 0; false when the hierarchy is deeper than the stack.
  bool cross(const Ray& ray, Crossings& out) const {
    if (nodes.empty()) return true;
    glm::vec3 inv;
    for (int a = 0; a < 3; ++a)
      inv[a] = 1.0f / (ray.dir[a] != 0.0f ? ray.dir[a] : std::copysign(1e-30f, ray.dir[a]));
    std::array<uint32_t, kStackDepth> stack;
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes[stack[--top]];
      const glm::vec3 t0 = (n.lo - ray.origin) * inv, t1 = (n.hi - ray.origin) * inv;
      const glm::vec3 near = glm::min(t0, t1), far = glm::max(t0, t1);
      const float enter = std::max({near.x, near.y, near.z, 0.0f});
      const float leave = std::min({far.x, far.y, far.z});
      if (!(enter <= leave)) continue;
      if (n.count == 0) {
        if (top + 2 > kStackDepth) return false;
        stack[top++] = n.first;
        stack[top++] = n.first + 1;
        continue;
      }
      for (uint32_t i = n.first; i < n.first + n.count; ++i) {
        const Triangle& tri = triangles[i];
        float t;
        if (hit(ray, tri, t)) out.add(t, tri.mesh, tri.outward, ray.dir);
      }
    }
    return true;
  }

  // Möller and Trumbore's test in double precision, edges included: a ray through an edge meets
  // both of its triangles (Crossings::add keeps one) rather than neither.
  static bool hit(const Ray& ray, const Triangle& tri, float& t_out) {
    const glm::dvec3 o(ray.origin), d(ray.dir), a(tri.a);
    const glm::dvec3 e1 = glm::dvec3(tri.b) - a, e2 = glm::dvec3(tri.c) - a;
    const glm::dvec3 p = glm::cross(d, e2);
    const double det = glm::dot(e1, p);
    if (det == 0.0) return false;
    const double inv = 1.0 / det;
    const glm::dvec3 s = o - a;
    const double u = glm::dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) return false;
    const glm::dvec3 q = glm::cross(s, e1);
    const double v = glm::dot(d, q) * inv;
    if (v < 0.0 || u + v > 1.0) return false;
    const double t = glm::dot(e2, q) * inv;
    if (!(t >= 0.0)) return false;
    t_out = static_cast<float>(t);
    return true;
  }
};

TubeClipMeshes::TubeClipMeshes(std::vector<std::shared_ptr<const Mesh>> meshes,
                               std::vector<bool> keep_inside, const std::string& object)
    : bvh_(std::make_unique<Bvh>()), meshes_(std::move(meshes)) {
  if (meshes_.size() > static_cast<size_t>(kMaxClipMeshes) || keep_inside.size() != meshes_.size())
    throw Error(fmt::format("streamlines '{}': {} clip meshes, at most {}", object, meshes_.size(),
                            kMaxClipMeshes));
  size_t triangles = 0;
  for (const auto& m : meshes_) triangles += m->triangles.size();
  // The triangles twice (a list, then the tree's order) and the nodes over them.
  check_memory(triangles * (2 * sizeof(Bvh::Triangle) + 2 * sizeof(Bvh::Node) / kLeafTriangles),
               fmt::format("streamlines '{}': its clip meshes' {} triangles", object, triangles));
  std::vector<Bvh::Triangle> all;
  for (size_t k = 0; k < meshes_.size(); ++k) {
    const Mesh& m = *meshes_[k];
    for (size_t t = 0; t < m.triangles.size(); ++t) {
      for (int c = 0; c < 3; ++c)
        if (m.triangles[t][c] >= m.positions.size())
          throw Error(
              fmt::format("streamlines '{}': clip mesh {} triangle {} names vertex {} of {}",
                          object, k, t, m.triangles[t][c], m.positions.size()));
      Bvh::Triangle tri{m.positions[m.triangles[t].x], m.positions[m.triangles[t].y],
                        m.positions[m.triangles[t].z], glm::vec3(0.0f), static_cast<uint32_t>(k)};
      // Wound outward: the right-handed normal points out of the mesh.
      const glm::vec3 n = glm::cross(tri.b - tri.a, tri.c - tri.a);
      const float len = glm::length(n);
      if (!(len > 0.0f)) continue;  // a degenerate triangle bounds nothing
      tri.outward = n / len;
      all.push_back(tri);
    }
    const PrimitiveMask bit = PrimitiveMask{1} << k;
    (keep_inside[k] ? rule_.ones : rule_.zeros) |= bit;
  }
  if (all.empty()) return;
  std::vector<uint32_t> order(all.size());
  std::iota(order.begin(), order.end(), 0u);
  bvh_->nodes.reserve(2 * all.size() / kLeafTriangles + 1);
  bvh_->nodes.resize(1);
  bvh_->build(0, order, 0, static_cast<uint32_t>(all.size()), all);
  bvh_->triangles.reserve(all.size());
  for (uint32_t i : order) bvh_->triangles.push_back(all[i]);
}

TubeClipMeshes::~TubeClipMeshes() = default;

void TubeClipMeshes::kept(const Ray& ray, Pieces& out) const {
  out.count = 0;
  Crossings all;
  // A pathological cutter (deeper than the stack, more crossings than kept) keeps nothing.
  if (!bvh_->cross(ray, all) || all.overflow) return;
  // The volumes' clip step on these crossings: windings from #back - #front, pieces where the
  // rule matches (frame/clip_intervals.hpp).
  const ClipView view{std::span<const int8_t>(kIdentitySlots.data(), meshes_.size()),
                      std::span<const ClipState>(&rule_, 1)};
  ClipPieces pieces;
  clip_volume(std::span<const Fragment>(all.row.data(), static_cast<size_t>(all.count)), view, 0,
              pieces);
  for (int p = 0; p < pieces.count; ++p) {
    out.piece[p].lo = end_at(pieces.piece[p].t0, all, -ray.dir);
    out.piece[p].hi = end_at(pieces.piece[p].t1, all, ray.dir);
  }
  out.count = pieces.count;
}

std::shared_ptr<const TubeClipMeshes> make_tube_clip_meshes(const StreamlineObject& object,
                                                            std::span<const MeshObject> meshes) {
  if (object.clip_meshes.empty()) return nullptr;
  std::vector<std::shared_ptr<const Mesh>> chosen;
  std::vector<bool> keep_inside;
  for (const ClipMesh& c : object.clip_meshes) {
    if (c.mesh < 0 || static_cast<size_t>(c.mesh) >= meshes.size() || !meshes[c.mesh].mesh)
      throw Error(
          fmt::format("streamlines '{}': clip mesh index {} is not a mesh of the scene ({})",
                      object.name, c.mesh, meshes.size()));
    chosen.push_back(meshes[c.mesh].mesh);
    keep_inside.push_back(c.keep_inside);
  }
  return std::make_shared<const TubeClipMeshes>(std::move(chosen), std::move(keep_inside),
                                                object.name);
}

}  // namespace imx
