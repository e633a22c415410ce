#include "io/mesh/vertex_normals.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <tuple>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <glm/glm.hpp>

#include "intermix/limits.hpp"
#include "io/mesh/vertex_weld.hpp"

namespace imx::detail {
namespace {

// Union-find over face corners, with path halving; a set's root is its lowest corner.
struct Groups {
  std::vector<uint32_t> parent;
  explicit Groups(size_t n) : parent(n) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const auto& r) {
      std::iota(parent.begin() + r.begin(), parent.begin() + r.end(),
                static_cast<uint32_t>(r.begin()));
    });
  }
  uint32_t find(uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void join(uint32_t a, uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

// The angle of triangle `tri` at its corner k, in double precision.
double corner_angle(const Mesh& mesh, const glm::uvec3& tri, int k) {
  const glm::dvec3 p[3] = {glm::dvec3(mesh.positions[tri.x]), glm::dvec3(mesh.positions[tri.y]),
                           glm::dvec3(mesh.positions[tri.z])};
  const glm::dvec3 a = p[(k + 1) % 3] - p[k], b = p[(k + 2) % 3] - p[k];
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// Calls fn(first, last) over ranges of [0, n) in parallel.
template <class Fn>
void in_parallel(size_t n, Fn&& fn) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n),
                    [&](const tbb::blocked_range<size_t>& r) { fn(r.begin(), r.end()); });
}

// The steps of compute_vertex_normals over one mesh, sharing its arrays. Every step runs on all
// cores yet gives the bits of one core: the welds sort, corners are grouped and summed per
// place (welded position) in corner order, and vertices are numbered by a prefix sum in corner
// order.
class NormalsBuilder {
 public:
  NormalsBuilder(const Mesh& mesh, std::vector<uint32_t>* origin)
      : mesh_(mesh),
        colored_(mesh.colors.size() == mesh.positions.size() && !mesh.colors.empty()),
        welded_(weld_vertices(mesh.positions, colored_ ? mesh.colors : std::vector<glm::vec3>{})),
        // Adjacency goes by position alone: a colour seam is no crease.
        by_position_(colored_ ? weld_vertices(mesh.positions) : Weld{}),
        place_(colored_ ? by_position_.id : welded_.id),
        origin_(origin),
        n_corners_(3 * mesh.triangles.size()),
        groups_(n_corners_) {}

  Mesh build(double crease_deg) {
    face_normals();
    rows();
    group(crease_deg);
    number();
    sum();
    add_degenerate();
    return std::move(out_);
  }

 private:
  uint32_t vertex_at(uint32_t c) const { return mesh_.triangles[c / 3][c % 3]; }
  bool degenerate(uint32_t c) const { return face_[c / 3] == glm::dvec3(0.0); }
  uint32_t& out_at(uint32_t c) { return out_.triangles[c / 3][c % 3]; }
  size_t places() const { return offsets_.size() - 1; }

  // Unit face normals in double precision; zero for a degenerate face.
  void face_normals() {
    face_.assign(mesh_.triangles.size(), glm::dvec3(0.0));
    in_parallel(face_.size(), [&](size_t t0, size_t t1) {
      for (size_t t = t0; t < t1; ++t) {
        const glm::uvec3& tri = mesh_.triangles[t];
        const glm::dvec3 p0(mesh_.positions[tri.x]), p1(mesh_.positions[tri.y]),
            p2(mesh_.positions[tri.z]);
        const glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
        const double len = glm::length(n);
        if (len > 0.0 && std::isfinite(len)) face_[t] = n / len;
      }
    });
  }

  // Corners around each place as compressed rows, each row in corner order.
  void rows() {
    const size_t n_places = colored_ ? by_position_.first.size() : welded_.first.size();
    offsets_.assign(n_places + 1, 0);
    in_parallel(n_corners_, [&](size_t c0, size_t c1) {
      for (size_t c = c0; c < c1; ++c)
        std::atomic_ref<uint32_t>(offsets_[place_[vertex_at(c)] + 1])
            .fetch_add(1, std::memory_order_relaxed);
    });
    std::partial_sum(offsets_.begin(), offsets_.end(), offsets_.begin());
    corners_.resize(n_corners_);
    std::vector<uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
    in_parallel(n_corners_, [&](size_t c0, size_t c1) {
      for (size_t c = c0; c < c1; ++c)
        corners_[std::atomic_ref<uint32_t>(fill[place_[vertex_at(c)]])
                     .fetch_add(1, std::memory_order_relaxed)] = static_cast<uint32_t>(c);
    });
    in_parallel(n_places, [&](size_t v0, size_t v1) {
      for (size_t v = v0; v < v1; ++v)
        std::sort(corners_.begin() + offsets_[v], corners_.begin() + offsets_[v + 1]);
    });
  }

  // Two corners at one place join when their faces share an edge there (the same other end)
  // and meet at no more than the crease angle; sorting by the other end finds the pairs in
  // O(k log k) for k corners, however many faces a hostile fan puts around one vertex. Joins
  // stay within a place, so places are grouped in parallel. Then one output vertex per
  // (welded vertex, group), numbered in order of its first corner: a group lies at one place,
  // so each place finds its first corners alone; the output triangles hold, per corner, that
  // first corner until number().
  void group(double crease_deg) {
    const double cos_crease =
        std::cos(std::clamp(crease_deg, 0.0, 180.0) * std::numbers::pi / 180.0);
    out_.triangles.resize(mesh_.triangles.size());
    is_first_.assign(n_corners_, 0);
    in_parallel(places(), [&](size_t v0, size_t v1) {
      std::vector<std::pair<uint32_t, uint32_t>> ends;             // (other end's place, corner)
      std::vector<std::tuple<uint32_t, uint32_t, uint32_t>> keys;  // (welded vertex, root, corner)
      for (size_t v = v0; v < v1; ++v) {
        ends.clear();
        for (uint32_t i = offsets_[v]; i < offsets_[v + 1]; ++i) {
          const uint32_t c = corners_[i], t = c / 3, k = c % 3;
          if (degenerate(c)) continue;
          ends.emplace_back(place_[mesh_.triangles[t][(k + 1) % 3]], c);
          ends.emplace_back(place_[mesh_.triangles[t][(k + 2) % 3]], c);
        }
        std::sort(ends.begin(), ends.end());
        for (size_t i = 1; i < ends.size(); ++i)
          if (ends[i].first == ends[i - 1].first &&
              glm::dot(face_[ends[i].second / 3], face_[ends[i - 1].second / 3]) >=
                  cos_crease - 1e-12)
            groups_.join(ends[i].second, ends[i - 1].second);

        keys.clear();
        for (uint32_t i = offsets_[v]; i < offsets_[v + 1]; ++i)
          if (const uint32_t c = corners_[i]; !degenerate(c))
            keys.emplace_back(welded_.id[vertex_at(c)], groups_.find(c), c);
        std::sort(keys.begin(), keys.end());
        uint32_t head = 0;
        for (size_t i = 0; i < keys.size(); ++i) {
          const auto [w, root, c] = keys[i];
          if (i == 0 || std::get<0>(keys[i - 1]) != w || std::get<1>(keys[i - 1]) != root) {
            head = c;
            is_first_[c] = 1;
          }
          out_at(c) = head;
        }
      }
    });
  }

  // Numbers by a prefix sum over chunks of corners; the firsts first, then the rest look theirs
  // up (a first corner always comes before the others of its vertex).
  void number() {
    constexpr size_t kChunk = size_t{1} << 16;
    const size_t chunks = (n_corners_ + kChunk - 1) / kChunk;
    std::vector<uint32_t> base(chunks + 1, 0);
    tbb::parallel_for(size_t{0}, chunks, [&](size_t k) {
      uint32_t count = 0;
      for (size_t c = k * kChunk; c < std::min(n_corners_, (k + 1) * kChunk); ++c)
        count += is_first_[c];
      base[k + 1] = count;
    });
    std::partial_sum(base.begin(), base.end(), base.begin());
    tbb::parallel_for(size_t{0}, chunks, [&](size_t k) {
      uint32_t next = base[k];
      for (size_t c = k * kChunk; c < std::min(n_corners_, (k + 1) * kChunk); ++c)
        if (is_first_[c]) out_at(static_cast<uint32_t>(c)) = next++;
    });
    in_parallel(n_corners_, [&](size_t c0, size_t c1) {
      for (uint32_t c = static_cast<uint32_t>(c0); c < c1; ++c)
        if (!is_first_[c] && !degenerate(c)) out_at(c) = out_at(out_at(c));
    });
    const size_t n_out = base[chunks];
    out_.positions.resize(n_out);
    out_.normals.resize(n_out);
    if (colored_) out_.colors.resize(n_out);
    if (origin_) origin_->assign(n_out, 0);
  }

  void put_vertex(uint32_t id, uint32_t w, const glm::dvec3& sum) {
    const uint32_t from = welded_.first[w];
    out_.positions[id] = mesh_.positions[from];
    if (colored_) out_.colors[id] = mesh_.colors[from];
    if (origin_) (*origin_)[id] = from;
    const double len = glm::length(sum);
    out_.normals[id] = glm::vec3(len > 0.0 && std::isfinite(len) ? sum / len : glm::dvec3(0.0));
  }

  // Each group's angle-weighted normal, summed in corner order, and its vertices' data.
  void sum() {
    in_parallel(places(), [&](size_t v0, size_t v1) {
      std::vector<glm::dvec3> sums;  // per corner of the row: the sum of the group it is root of
      for (size_t v = v0; v < v1; ++v) {
        const auto row_begin = corners_.begin() + offsets_[v],
                   row_end = corners_.begin() + offsets_[v + 1];
        sums.assign(static_cast<size_t>(row_end - row_begin), glm::dvec3(0.0));
        auto slot = [&](uint32_t c) { return std::lower_bound(row_begin, row_end, c) - row_begin; };
        for (auto it = row_begin; it != row_end; ++it)
          if (!degenerate(*it))
            sums[slot(groups_.find(*it))] +=
                corner_angle(mesh_, mesh_.triangles[*it / 3], static_cast<int>(*it % 3)) *
                face_[*it / 3];
        for (auto it = row_begin; it != row_end; ++it)
          if (is_first_[*it])
            put_vertex(out_at(*it), welded_.id[vertex_at(*it)], sums[slot(groups_.find(*it))]);
      }
    });
  }

  // Degenerate triangles come last and reuse a vertex of their corner where there is one: they
  // show nothing and need no normal.
  void add_degenerate() {
    if (std::find(face_.begin(), face_.end(), glm::dvec3(0.0)) == face_.end()) return;
    std::vector<uint32_t> any_vertex(welded_.first.size(), UINT32_MAX);
    for (uint32_t c = 0; c < n_corners_; ++c)
      if (is_first_[c] && any_vertex[welded_.id[vertex_at(c)]] == UINT32_MAX)
        any_vertex[welded_.id[vertex_at(c)]] = out_at(c);
    for (uint32_t c = 0; c < n_corners_; ++c) {
      if (!degenerate(c)) continue;
      const uint32_t w = welded_.id[vertex_at(c)];
      if (any_vertex[w] == UINT32_MAX) {
        any_vertex[w] = static_cast<uint32_t>(out_.positions.size());
        out_.positions.emplace_back();
        out_.normals.emplace_back();
        if (colored_) out_.colors.emplace_back();
        if (origin_) origin_->emplace_back();
        put_vertex(any_vertex[w], w, glm::dvec3(0.0));
      }
      out_at(c) = any_vertex[w];
    }
  }

  const Mesh& mesh_;
  const bool colored_;
  const Weld welded_, by_position_;
  const std::vector<uint32_t>& place_;
  std::vector<uint32_t>* origin_;
  const size_t n_corners_;
  Groups groups_;
  std::vector<glm::dvec3> face_;
  std::vector<uint32_t> offsets_, corners_;
  std::vector<uint8_t> is_first_;
  Mesh out_;
};

}  // namespace

void compute_vertex_normals(Mesh& mesh, double crease_deg, std::vector<uint32_t>* origin) {
  check_memory(uint64_t{mesh.triangles.size()} * 72 + uint64_t{mesh.positions.size()} * 72,
               "computing the vertex normals of a mesh");
  Mesh out = NormalsBuilder(mesh, origin).build(crease_deg);
  mesh = std::move(out);
}

}  // namespace imx::detail
