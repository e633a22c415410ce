// Micro-benchmarks of the volume engine's building blocks: sampling, brick traversal, and the
// tables rebuilt on a transfer-function change.
#include <benchmark/benchmark.h>

#include <random>
#include <string>

#include "bench_volumes.hpp"
#include "volume/any_grid.hpp"
#include "volume/brick_dda.hpp"
#include "volume/brick_min_max.hpp"
#include "volume/brick_occupancy.hpp"
#include "volume/gradient_volume.hpp"
#include "volume/octant_distance.hpp"
#include "volume/preintegration_table.hpp"
#include "volume/simd_targets.hpp"
#include "volume/tf_emptiness.hpp"
#include "volume/tf_lut.hpp"

// Compiled once, before the per-target part (the lane walk, foreach_target below).
#ifndef IMX_BENCH_VOLUME_BENCH_ONCE_
#define IMX_BENCH_VOLUME_BENCH_ONCE_
namespace imx {
namespace {

constexpr int kSide = 256;

template <class T>
const VolumeData& volume() {
  static auto v = bench::shell_volume<T>(kSide, std::is_same_v<T, int16_t> ? 8.0f : 1.0f,
                                         std::is_same_v<T, int16_t> ? -1024.0f : 0.0f);
  return *v;
}

TfLut shell_lut() {
  TransferFunction tf;
  tf.points = {{0.0, {1, 1, 1, 0}},
               {150.0, {1, 0.8f, 0.6f, 0}},
               {200.0, {1, 0.9f, 0.8f, 0.6f}},
               {255.0, {1, 1, 1, 0.9f}}};
  return TfLut(tf);
}

// Random positions, sampled in order: the cost of one trilinear fetch with cache misses.
template <class T>
void BM_TrilinearRandom(benchmark::State& state) {
  VoxelGrid<T> g = AnyGrid(volume<T>()).template as<T>();
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.0f, kSide - 1.0f);
  std::vector<glm::vec3> pos(1 << 14);
  for (auto& p : pos) p = {u(rng), u(rng), u(rng)};
  for (auto _ : state) {
    float sum = 0.0f;
    for (const glm::vec3& p : pos) sum += g.sample(p);
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pos.size()));
}
BENCHMARK(BM_TrilinearRandom<uint8_t>);
BENCHMARK(BM_TrilinearRandom<int16_t>);
BENCHMARK(BM_TrilinearRandom<float>);

// Half-voxel steps along oblique rays: the access pattern of a ray marcher.
template <class T>
void BM_TrilinearAlongRays(benchmark::State& state) {
  VoxelGrid<T> g = AnyGrid(volume<T>()).template as<T>();
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<std::pair<glm::vec3, glm::vec3>> rays(64);
  for (auto& r : rays)
    r = {glm::vec3(kSide / 2.0f), glm::normalize(glm::vec3(u(rng), u(rng), u(rng)))};
  int64_t samples = 0;
  for (auto _ : state) {
    float sum = 0.0f;
    for (const auto& [o, d] : rays)
      for (float t = 0.0f; t < kSide / 2.0f - 1.0f; t += 0.5f) sum += g.sample(o + t * d);
    benchmark::DoNotOptimize(sum);
    samples += static_cast<int64_t>(rays.size()) * (kSide - 2);
  }
  state.SetItemsProcessed(samples);
}
BENCHMARK(BM_TrilinearAlongRays<uint8_t>);
BENCHMARK(BM_TrilinearAlongRays<int16_t>);
BENCHMARK(BM_TrilinearAlongRays<float>);

struct Rays {
  std::vector<glm::vec3> origin, dir;
  std::vector<float> t0, t1;
};

// Rays from a sphere around the grid toward random points inside it, clipped to [0, N-1]^3.
Rays random_rays(int count) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Rays r;
  glm::vec3 c(kSide / 2.0f), hi(kSide - 1.0f);
  while (static_cast<int>(r.origin.size()) < count) {
    glm::vec3 from = c + 2.0f * kSide * glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
    glm::vec3 to = c + 0.45f * kSide * glm::vec3(u(rng), u(rng), u(rng));
    glm::vec3 d = glm::normalize(to - from);
    float t0 = 0.0f, t1 = 1e30f;
    for (int a = 0; a < 3; ++a) {
      float ta = (0.0f - from[a]) / d[a], tb = (hi[a] - from[a]) / d[a];
      t0 = std::max(t0, std::min(ta, tb));
      t1 = std::min(t1, std::max(ta, tb));
    }
    if (!(t1 > t0)) continue;
    r.origin.push_back(from);
    r.dir.push_back(d);
    r.t0.push_back(t0);
    r.t1.push_back(t1);
  }
  return r;
}

// Every brick of a 256^3 grid's 32^3 bricks that each ray crosses.
void BM_BrickDdaFullWalk(benchmark::State& state) {
  BrickGrid grid(glm::ivec3(kSide), 8);
  Rays rays = random_rays(1024);
  int64_t bricks = 0;
  for (auto _ : state) {
    for (size_t i = 0; i < rays.origin.size(); ++i) {
      BrickDda dda(grid, rays.origin[i], rays.dir[i], rays.t0[i], rays.t1[i]);
      for (; !dda.done(); dda.next()) {
        benchmark::DoNotOptimize(dda.span());
        ++bricks;
      }
    }
  }
  state.SetItemsProcessed(bricks);
}
BENCHMARK(BM_BrickDdaFullWalk);

// Block skipping alone on the shell volume: every brick is visited and tested; items are the
// non-empty bricks reached (compare with BM_BrickDdaWithJumps).
void BM_BrickDdaBlockSkip(benchmark::State& state) {
  BrickMinMax mm(AnyGrid(volume<uint8_t>()), glm::ivec3(8));
  BrickOccupancy occ(mm, TfEmptiness(shell_lut()));
  Rays rays = random_rays(1024);
  int64_t visible = 0;
  for (auto _ : state) {
    for (size_t i = 0; i < rays.origin.size(); ++i) {
      BrickDda dda(mm.grid(), rays.origin[i], rays.dir[i], rays.t0[i], rays.t1[i]);
      for (; !dda.done(); dda.next())
        if (occ.occupied(dda.brick())) {
          benchmark::DoNotOptimize(dda.span());
          ++visible;
        }
    }
  }
  state.SetItemsProcessed(visible);
}
BENCHMARK(BM_BrickDdaBlockSkip);

// The same rays with distance jumps over the shell volume's empty bricks; items are the
// non-empty bricks reached.
void BM_BrickDdaWithJumps(benchmark::State& state) {
  BrickMinMax mm(AnyGrid(volume<uint8_t>()), glm::ivec3(8));
  BrickOccupancy occ(mm, TfEmptiness(shell_lut()));
  Rays rays = random_rays(1024);
  int64_t visible = 0, stops = 0;
  for (auto _ : state) {
    for (size_t i = 0; i < rays.origin.size(); ++i) {
      BrickDda dda(mm.grid(), rays.origin[i], rays.dir[i], rays.t0[i], rays.t1[i]);
      while (!dda.done()) {
        ++stops;
        uint8_t d = occ.distance(dda.brick(), dda.octant());
        if (d == 0) {
          benchmark::DoNotOptimize(dda.span());
          ++visible;
        }
        dda.skip(d);
      }
    }
  }
  state.SetItemsProcessed(visible);
  state.counters["stops_per_visible"] = static_cast<double>(stops) / std::max<int64_t>(visible, 1);
}
BENCHMARK(BM_BrickDdaWithJumps);

// From where each ray enters the grid to its first non-empty brick on the shell volume, with
// distance jumps, one ray at a time: what the marcher does before its first sample.
void BM_FirstOccupiedBrickDda(benchmark::State& state) {
  BrickMinMax mm(AnyGrid(volume<uint8_t>()), glm::ivec3(8));
  BrickOccupancy occ(mm, TfEmptiness(shell_lut()));
  Rays rays = random_rays(1024);
  for (auto _ : state) {
    for (size_t i = 0; i < rays.origin.size(); ++i) {
      BrickDda dda(mm.grid(), rays.origin[i], rays.dir[i], rays.t0[i], rays.t1[i]);
      while (!dda.done() && !occ.occupied(dda.brick()))
        dda.skip(occ.distance(dda.brick(), dda.octant()));
      benchmark::DoNotOptimize(dda.span());
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(rays.origin.size()));
}
BENCHMARK(BM_FirstOccupiedBrickDda);

void BM_PreintegrationBuild(benchmark::State& state) {
  TfLut lut = shell_lut();
  int size = static_cast<int>(state.range(0));
  for (auto _ : state) {
    PreintegrationTable table(lut, 0.5f, -50.0f, 300.0f, size, 1);
    benchmark::DoNotOptimize(table.entry(1, 2));
  }
}
BENCHMARK(BM_PreintegrationBuild)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);

void BM_PreintegrationLookup(benchmark::State& state) {
  PreintegrationTable table(shell_lut(), 0.5f);
  PreintegrationView view = table.view();
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(0.0f, 255.0f);
  std::vector<float> s(4097);
  for (float& v : s) v = u(rng);
  for (auto _ : state) {
    glm::vec4 acc(0.0f);
    for (size_t i = 0; i + 1 < s.size(); ++i) acc += view.lookup(s[i], s[i + 1]);
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(s.size() - 1));
}
BENCHMARK(BM_PreintegrationLookup);

// The per-volume scan (TF-independent), on one thread.
template <class T>
void BM_BrickMinMax256(benchmark::State& state) {
  AnyGrid grid(volume<T>());
  for (auto _ : state) benchmark::DoNotOptimize(BrickMinMax(grid, glm::ivec3(8), 1));
}
BENCHMARK(BM_BrickMinMax256<int16_t>)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BrickMinMax256<float>)->Unit(benchmark::kMillisecond);

// The precomputed gradients of a 256^3 volume, built once per volume (a first image's cost), on
// one thread: packed for 8-bit voxels, int16 for the others.
template <class T>
void BM_GradientVolume256(benchmark::State& state) {
  AnyGrid grid(volume<T>());
  for (auto _ : state) benchmark::DoNotOptimize(GradientVolume(grid, 1));
}
BENCHMARK(BM_GradientVolume256<uint8_t>)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GradientVolume256<int16_t>)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GradientVolume256<float>)->Unit(benchmark::kMillisecond);

// What a TF change costs: emptiness prefix, occupancy and distance map of 32^3 bricks.
void BM_TfChangeRebuild(benchmark::State& state) {
  BrickMinMax mm(AnyGrid(volume<uint8_t>()), glm::ivec3(8));
  TfLut lut = shell_lut();
  for (auto _ : state) benchmark::DoNotOptimize(BrickOccupancy(mm, TfEmptiness(lut)));
}
BENCHMARK(BM_TfChangeRebuild)->Unit(benchmark::kMicrosecond);

void BM_DistanceMap(benchmark::State& state) {
  int n = static_cast<int>(state.range(0));
  std::vector<uint8_t> occ(static_cast<size_t>(n) * n * n), out(kOctants * occ.size());
  std::mt19937 rng(5);
  for (auto& o : occ) o = rng() % 64 == 0;
  for (auto _ : state) {
    octant_distance(occ, glm::ivec3(n), out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(occ.size()));
}
BENCHMARK(BM_DistanceMap)->Arg(32)->Arg(64)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace imx
#endif  // IMX_BENCH_VOLUME_BENCH_ONCE_

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "volume_bench.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include "volume/lane_bricks-inl.hpp"

HWY_BEFORE_NAMESPACE();
namespace imx::HWY_NAMESPACE {

// BM_FirstOccupiedBrickDda's walks kLanes rays at a time in this target's lanes (LaneBricks, as
// the packet path does them).
void first_occupied_lane_bricks(benchmark::State& state) {
  using namespace lanes;
  BrickMinMax mm(AnyGrid(volume<uint8_t>()), glm::ivec3(8));
  BrickOccupancy occ(mm, TfEmptiness(shell_lut()));
  const LaneBricks walker(occ, SkipMode::distance);
  Rays rays = random_rays(1024);
  LaneBricks::Rays r;
  for (auto _ : state) {
    for (size_t first = 0; first + kLanes <= rays.origin.size(); first += kLanes) {
      HWY_ALIGN float o[3][kLanes], d[3][kLanes], t0[kLanes], t1[kLanes];
      for (int l = 0; l < kLanes; ++l) {
        for (int a = 0; a < 3; ++a)
          o[a][l] = rays.origin[first + l][a], d[a][l] = rays.dir[first + l][a];
        t0[l] = rays.t0[first + l], t1[l] = rays.t1[first + l];
      }
      const float* const origin[3] = {o[0], o[1], o[2]};
      const float* const dir[3] = {d[0], d[1], d[2]};
      walker.rays(origin, dir, r);
      VF enter = load(t1), leave = enter;
      unsigned none = walker.first_occupied(r, kAllLanes, load(t0), load(t1), enter, leave);
      benchmark::DoNotOptimize(none);
      benchmark::DoNotOptimize(hwy::HWY_NAMESPACE::GetLane(enter));
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(rays.origin.size()));
  state.SetLabel(std::to_string(kLanes) + " lanes");
}

}  // namespace imx::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace imx {
namespace {

HWY_EXPORT(first_occupied_lane_bricks);

// BM_FirstOccupiedLaneBricks/<target> for each target the machine runs.
const bool registered = [] {
  for (const std::string& name : simd_targets())
    benchmark::RegisterBenchmark(("BM_FirstOccupiedLaneBricks/" + name).c_str(),
                                 [name](benchmark::State& state) {
                                   limit_simd_target(name);
                                   HWY_DYNAMIC_DISPATCH(first_occupied_lane_bricks)(state);
                                   limit_simd_target("");
                                 });
  return true;
}();

}  // namespace
}  // namespace imx
#endif  // HWY_ONCE
