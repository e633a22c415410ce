// A vector of 32-bit words at random indices, the fetch under every packet sample, on each SIMD
// target this build compiled that the machine runs: Highway's gather (GatherIndex: the gather
// instruction on AVX2 and AVX-512) against one scalar load per lane, stored and loaded again as a
// vector, and against lanes::gather_words (the label says which way it takes: kHardwareGather).
// Items are lanes, so the rates compare per lane across targets (docs/performance.md, stop 44:
// the AMD machine where loads beat AVX2's gathers).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "volume/simd_targets.hpp"

// Compiled once, before the per-target parts.
#ifndef IMX_BENCH_LANE_FETCH_BENCH_ONCE_
#define IMX_BENCH_LANE_FETCH_BENCH_ONCE_
namespace imx::lane_fetch_bench {

// 256 KiB of words (in L2, as a packet's neighbourhood of voxels is) and random indices.
struct FetchData {
  std::vector<int32_t> words = std::vector<int32_t>(1 << 16);
  std::vector<int32_t> index = std::vector<int32_t>(1 << 15);
  FetchData() {
    std::mt19937 rng(7);
    for (size_t i = 0; i < words.size(); ++i) words[i] = static_cast<int32_t>(i * 7);
    for (int32_t& i : index) i = static_cast<int32_t>(rng() % words.size());
  }
};
inline const FetchData& data() {
  static const FetchData d;
  return d;
}

}  // namespace imx::lane_fetch_bench
#endif  // IMX_BENCH_LANE_FETCH_BENCH_ONCE_

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "lane_fetch_bench.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include "volume/lanes-inl.hpp"

HWY_BEFORE_NAMESPACE();
namespace imx::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;
using namespace lanes;

// One scalar load per lane, stored and loaded again as a vector (gather_words where the target
// does not gather).
HWY_INLINE VI loaded_words(const int32_t* base, VI index) {
  HWY_ALIGN int32_t at[kLanes];
  HWY_ALIGN int32_t word[kLanes];
  store(index, at);
  for (int l = 0; l < kLanes; ++l) word[l] = base[at[l]];
  return load(word);
}

// Sums the words at every index, a vector at a time: 0 by Highway's gather, 1 by scalar loads
// stored and loaded again, 2 by lanes::gather_words.
void lane_fetch(benchmark::State& state, int way) {
  const lane_fetch_bench::FetchData& d = lane_fetch_bench::data();
  VI sum = hn::Zero(DI());
  for (auto _ : state) {
    for (size_t k = 0; k + kLanes <= d.index.size(); k += kLanes) {
      const VI at = hn::LoadU(DI(), &d.index[k]);
      sum = hn::Add(sum, way == 0   ? hn::GatherIndex(DI(), d.words.data(), at)
                         : way == 1 ? loaded_words(d.words.data(), at)
                                    : gather_words<4>(d.words.data(), at));
    }
    benchmark::DoNotOptimize(hn::GetLane(sum));
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(d.index.size()));
  state.SetLabel(std::to_string(kLanes) + " lanes, gather_words " +
                 (kHardwareGather ? "gathers" : "loads"));
}

}  // namespace imx::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace imx {
namespace {

HWY_EXPORT(lane_fetch);

// BM_LaneFetch/<target>/gather, /loads and /gather_words for each target the machine runs.
const bool registered = [] {
  const char* const ways[] = {"gather", "loads", "gather_words"};
  for (const std::string& name : simd_targets())
    for (int way = 0; way < 3; ++way)
      benchmark::RegisterBenchmark(("BM_LaneFetch/" + name + "/" + ways[way]).c_str(),
                                   [name, way](benchmark::State& state) {
                                     limit_simd_target(name);
                                     HWY_DYNAMIC_DISPATCH(lane_fetch)(state, way);
                                     limit_simd_target("");
                                   });
  return true;
}();

}  // namespace
}  // namespace imx
#endif  // HWY_ONCE
