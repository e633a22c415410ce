#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "random_volumes.hpp"
#include "volume/brick_dda.hpp"
#include "volume/brick_min_max.hpp"
#include "volume/brick_occupancy.hpp"
#include "volume/octant_distance.hpp"
#include "volume/prepared_volume.hpp"

namespace imx {
namespace {

// Brick shapes the trials take in turn: cubes, and the flat and uneven ones that
// BrickGrid::shape_for gives volumes of thick slices.
glm::ivec3 trial_shape(int trial) {
  constexpr glm::ivec3 shapes[] = {{8, 8, 8}, {4, 4, 4}, {8, 8, 1}, {3, 8, 2}};
  return shapes[trial % 4];
}

// A volume placed obliquely, so index-space directions are not unit and t is world mm.
struct PlacedGrid {
  VolumeObject obj;
  std::unique_ptr<PreparedVolume> pv;
  BrickGrid grid;
  PlacedGrid(glm::ivec3 dims, glm::ivec3 brick, std::mt19937& rng, VolumeData data = {}) {
    if (data.dims.x == 0) {
      data.dims = dims;
      data.voxels = std::vector<uint8_t>(static_cast<size_t>(dims.x) * dims.y * dims.z, 0);
    }
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(u(rng), u(rng), u(rng)) * 10.0);
    m = glm::rotate(m, 2.0 * u(rng), glm::normalize(glm::dvec3(u(rng), u(rng), u(rng) + 2.0)));
    m = glm::scale(m, glm::dvec3(0.6 + 0.5 * (u(rng) + 1), 0.6 + 0.5 * (u(rng) + 1), 1.5));
    obj.name = "v";
    obj.transfer_function.points = {{0.0, glm::vec4(1)}};
    obj.index_to_world = m;
    obj.data = std::make_shared<VolumeData>(std::move(data));
    pv = std::make_unique<PreparedVolume>(obj);
    grid = BrickGrid(dims, brick);
  }
  glm::vec3 index_origin(const Ray& r) const { return pv->to_index(r.origin); }
  glm::vec3 index_dir(const Ray& r) const { return glm::mat3(pv->world_to_index) * r.dir; }
};

// Random world rays toward the volume: from outside, from inside, and along index axes (with
// origins on brick boundaries some of the time).
Ray random_ray(const PlacedGrid& s, std::mt19937& rng, int kind) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  glm::vec3 hi(s.grid.voxel_dims - 1);
  glm::vec3 target = hi * glm::vec3(u(rng), u(rng), u(rng));
  glm::vec3 dir_index;
  if (kind % 4 == 2) {  // along an index axis, sometimes exactly on brick faces
    int a = static_cast<int>(u(rng) * 3) % 3;
    dir_index = glm::vec3(0.0f);
    dir_index[a] = u(rng) < 0.5f ? 1.0f : -1.0f;
    if (u(rng) < 0.5f)
      for (int b = 0; b < 3; ++b)
        if (b != a)
          target[b] = std::min(hi[b], static_cast<float>(s.grid.size[b] * (int)(u(rng) * 4)));
  } else if (kind % 4 == 3) {  // a diagonal of the index lattice
    dir_index = glm::vec3(u(rng) < 0.5f ? 1 : -1, u(rng) < 0.5f ? 1 : -1, u(rng) < 0.5f ? 1 : -1);
    target = glm::floor(target / glm::vec3(s.grid.size)) * glm::vec3(s.grid.size);
  } else {
    dir_index = glm::vec3(u(rng), u(rng), u(rng)) * 2.0f - 1.0f;
  }
  glm::vec3 world_target = glm::vec3(s.obj.index_to_world * glm::dvec4(target, 1.0));
  glm::vec3 dir = glm::normalize(glm::mat3(s.obj.index_to_world) * dir_index);
  float back = kind % 2 == 0 ? 400.0f : 0.0f;  // odd kinds start inside the volume
  return Ray{world_target - back * dir, dir};
}

struct Visit {
  glm::ivec3 brick;
  float t_enter, t_exit;
};

std::vector<Visit> walk(const PlacedGrid& s, const Ray& r, RayInterval iv,
                        const BrickOccupancy* skip = nullptr) {
  std::vector<Visit> out;
  BrickDda dda(s.grid, s.index_origin(r), s.index_dir(r), iv.t0, iv.t1);
  for (int guard = 0; !dda.done() && guard < 100000; ++guard) {
    out.push_back({dda.brick(), dda.t_enter(), dda.t_exit()});
    if (skip && !skip->occupied(dda.brick()))
      dda.skip(skip->distance(dda.brick(), dda.octant()));
    else
      dda.next();
  }
  return out;
}

// The brick whose half-open cell holds p, clamped to the grid, in double precision.
glm::ivec3 brick_at(const BrickGrid& g, glm::dvec3 p) {
  glm::ivec3 b;
  for (int a = 0; a < 3; ++a)
    b[a] = static_cast<int>(
        std::clamp(std::floor(p[a] / g.size[a]), 0.0, static_cast<double>(g.dims[a] - 1)));
  return b;
}

// The bricks met by points at the centres of n equal steps over [t0, t1], in order, on the
// same index-space ray the DDA walks but evaluated in double precision.
std::vector<glm::ivec3> fine_walk(const PlacedGrid& s, const Ray& r, RayInterval iv, int n) {
  glm::dvec3 o(s.index_origin(r)), d(s.index_dir(r));
  std::vector<glm::ivec3> out;
  for (int i = 0; i < n; ++i) {
    double t = iv.t0 + (static_cast<double>(iv.t1) - iv.t0) * (i + 0.5) / n;
    glm::dvec3 p = o + t * d;
    glm::ivec3 b = brick_at(s.grid, p);
    if (out.empty() || out.back() != b) out.push_back(b);
  }
  return out;
}

// Whether p lies in brick b's cell widened by eps (narrowed when eps < 0); border cells reach
// to infinity, as positions outside the grid clamp to them.
bool in_cell(const BrickGrid& g, glm::ivec3 b, glm::dvec3 p, double eps) {
  for (int a = 0; a < 3; ++a) {
    if (b[a] > 0 && p[a] < b[a] * g.size[a] - eps) return false;
    if (b[a] < g.dims[a] - 1 && p[a] > (b[a] + 1) * g.size[a] + eps) return false;
  }
  return true;
}

TEST(BrickDda, VisitsExactlyTheBricksOfAFineWalk) {
  std::mt19937 rng(21);
  std::uniform_int_distribution<int> size(5, 60);
  int rays = 0, exact = 0;
  for (int trial = 0; trial < 30; ++trial) {
    PlacedGrid s({size(rng), size(rng), size(rng)}, trial_shape(trial), rng);
    for (int k = 0; k < 40; ++k) {
      Ray r = random_ray(s, rng, k);
      RayInterval iv = s.pv->intersect(r);
      if (iv.empty()) continue;
      ++rays;
      std::string where = "trial " + std::to_string(trial) + " ray " + std::to_string(k);
      std::vector<Visit> dda = walk(s, r, iv);
      ASSERT_FALSE(dda.empty());
      // A contiguous cover of [t0, t1] by face neighbours, no brick twice.
      EXPECT_EQ(dda.front().t_enter, iv.t0) << where;
      EXPECT_EQ(dda.back().t_exit, iv.t1) << where;
      for (size_t i = 1; i < dda.size(); ++i) {
        ASSERT_EQ(dda[i].t_enter, dda[i - 1].t_exit) << where;
        glm::ivec3 d = glm::abs(dda[i].brick - dda[i - 1].brick);
        ASSERT_EQ(d.x + d.y + d.z, 1) << where;
        for (size_t j = 0; j < i; ++j) ASSERT_NE(dda[i].brick, dda[j].brick) << where;
      }
      // Float positions of a ray that runs along a brick face may fall on either side of it
      // (o + t d rounds): allow that much, and no more.
      glm::dvec3 o(s.index_origin(r)), d(s.index_dir(r));
      const double eps = 2e-4;
      // Every span's points are in its brick...
      for (const Visit& v : dda)
        for (double f : {0.01, 0.5, 0.99}) {
          double t = v.t_enter + f * (static_cast<double>(v.t_exit) - v.t_enter);
          ASSERT_TRUE(in_cell(s.grid, v.brick, o + t * d, 2e-4 + 1e-5 * std::abs(t)))
              << where << " brick " << v.brick.x << "," << v.brick.y << "," << v.brick.z;
        }
      // ...and every point of a fine walk is in the brick of the span that holds it.
      const int n = 20000;
      size_t span = 0;
      for (int i = 0; i < n; ++i) {
        double t = iv.t0 + (static_cast<double>(iv.t1) - iv.t0) * (i + 0.5) / n;
        while (span + 1 < dda.size() && t >= dda[span].t_exit) ++span;
        ASSERT_TRUE(in_cell(s.grid, dda[span].brick, o + t * d, eps + 1e-5 * std::abs(t)))
            << where << " t " << t << ": the DDA is in brick " << dda[span].brick.x << ","
            << dda[span].brick.y << "," << dda[span].brick.z;
      }
      // Away from faces the sequences agree exactly (spans longer than a fine step).
      std::vector<glm::ivec3> fine = fine_walk(s, r, iv, n), long_spans;
      for (const Visit& v : dda)
        if (v.t_exit - v.t_enter > 2.0f * (iv.t1 - iv.t0) / n) long_spans.push_back(v.brick);
      exact += long_spans == fine;
    }
  }
  EXPECT_GT(rays, 800);
  EXPECT_GT(exact, rays * 9 / 10);
}

// Distance jumps meet every occupied brick that stepping brick by brick meets, with the same
// intervals, and every occupied brick a fine walk meets; and they do skip.
struct JumpStats {
  int steps = 0, jumps = 0, checked = 0, on_faces = 0;
};

void check_jumps(const PlacedGrid& s, const BrickOccupancy& occ, std::mt19937& rng,
                 JumpStats& stats) {
  int& checked = stats.checked;
  int& on_faces = stats.on_faces;
  for (int k = 0; k < 40; ++k) {
    Ray r = random_ray(s, rng, k);
    RayInterval iv = s.pv->intersect(r);
    if (iv.empty()) continue;
    std::vector<Visit> all = walk(s, r, iv), jumped = walk(s, r, iv, &occ);
    std::vector<Visit> want;
    for (const Visit& v : all)
      if (occ.occupied(v.brick)) want.push_back(v);
    std::vector<Visit> got;
    for (const Visit& v : jumped)
      if (occ.occupied(v.brick)) got.push_back(v);
    ASSERT_EQ(got.size(), want.size()) << "ray " << k;
    for (size_t i = 0; i < got.size(); ++i) {
      ASSERT_EQ(got[i].brick, want[i].brick) << "ray " << k << " visit " << i;
      ASSERT_EQ(got[i].t_enter, want[i].t_enter);
      ASSERT_EQ(got[i].t_exit, want[i].t_exit);
    }
    // Brute force: every point of a fine walk that lies in an occupied brick is inside a span
    // the jumping walk stopped at in that brick. Points within float noise of a face may be
    // given to the neighbour (whose closed region holds the face too), so they are not judged.
    glm::dvec3 o(s.index_origin(r)), d(s.index_dir(r));
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      double t = iv.t0 + (static_cast<double>(iv.t1) - iv.t0) * (i + 0.5) / n;
      glm::dvec3 p = o + t * d;
      glm::ivec3 b = brick_at(s.grid, p);
      if (!occ.occupied(b)) continue;
      double eps = 2e-4 + 1e-5 * std::abs(t);
      if (!in_cell(s.grid, b, p, -eps)) {
        ++on_faces;
        continue;
      }
      ++checked;
      bool met = std::any_of(got.begin(), got.end(), [&](const Visit& v) {
        return v.brick == b && t >= v.t_enter - eps && t <= v.t_exit + eps;
      });
      ASSERT_TRUE(met) << "ray " << k << " skipped occupied brick " << b.x << "," << b.y << ","
                       << b.z << " at t " << t;
    }
    stats.steps += static_cast<int>(all.size());
    stats.jumps += static_cast<int>(jumped.size());
  }
}

TEST(BrickDda, DistanceJumpsNeverSkipAnOccupiedBrick) {
  std::mt19937 rng(22);
  std::uniform_int_distribution<int> size(20, 90);
  JumpStats stats;
  for (int trial = 0; trial < 24; ++trial) {
    // Real volumes under random TFs...
    glm::ivec3 dims(size(rng), size(rng), size(rng));
    VolumeData vol = test::blob_volume<uint8_t>(dims, rng, 1.0f, 0.0f, 1 + trial % 3);
    BrickMinMax mm(AnyGrid(vol), trial_shape(trial));
    TfLut lut(test::random_tf(rng, 20.0f, 255.0f));
    PlacedGrid s(dims, mm.grid().size, rng, vol);
    BrickOccupancy occ(mm, TfEmptiness(lut));
    check_jumps(s, occ, rng, stats);
  }
  EXPECT_LT(stats.jumps * 2, stats.steps) << "jumps hardly skipped anything";
  EXPECT_GT(stats.checked, 100000);
  EXPECT_LT(stats.on_faces * 4, stats.checked) << "too many points left out as on a face";
}

TEST(BrickOccupancy, DistanceIsTheOctantTransformOfOccupancy) {
  std::mt19937 rng(23);
  VolumeData vol = test::blob_volume<int16_t>({70, 50, 60}, rng, 4.0f, -500.0f, 3);
  BrickMinMax mm(AnyGrid(vol), glm::ivec3(8, 4, 2));
  TfLut lut(test::random_tf(rng, -400.0f, 520.0f));
  BrickOccupancy occ(mm, TfEmptiness(lut));
  const BrickGrid& g = occ.grid();
  std::vector<uint8_t> flags(g.count()), dist(kOctants * g.count());
  TfEmptiness e(lut);
  for (size_t n = 0; n < g.count(); ++n) {
    glm::vec2 r = mm.ranges()[n];
    flags[n] = occ.padded_distances()[kOctants * n] == 0;
    ASSERT_EQ(flags[n] == 0, e.is_empty(r.x - 1e-2f, r.y + 1e-2f)) << n;
  }
  octant_distance(flags, g.dims, dist);
  EXPECT_TRUE(std::equal(dist.begin(), dist.end(), occ.padded_distances()));
  EXPECT_GT(occ.occupied_count(), 0u);
  EXPECT_LT(occ.occupied_count(), g.count());
}

}  // namespace
}  // namespace imx
