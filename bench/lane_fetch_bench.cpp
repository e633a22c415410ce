// Eight 32-bit words at eight random indices, the fetch under every packet sample: AVX2's gather
// instruction against lanes::gather_words (eight scalar loads), and AVX-512's 16-lane gather
// where the CPU has it. Items are lanes, so the rates compare per lane (docs/performance.md,
// stop 44: why the packet kernels load instead of gathering).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>
#include <vector>

#include "volume/lanes.hpp"

#if IMX_PACKET_LANES
namespace imx {
namespace {

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
const FetchData& data() {
  static const FetchData d;
  return d;
}

template <bool Loads>
void BM_LaneFetch8(benchmark::State& state) {
  const FetchData& d = data();
  __m256i sum = _mm256_setzero_si256();
  for (auto _ : state) {
    for (size_t k = 0; k < d.index.size(); k += lanes::kLanes) {
      const __m256i at = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&d.index[k]));
      sum = _mm256_add_epi32(sum, Loads ? lanes::gather_words<4>(d.words.data(), at)
                                        : _mm256_i32gather_epi32(d.words.data(), at, 4));
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(d.index.size()));
}
BENCHMARK(BM_LaneFetch8<false>)->Name("BM_LaneFetch8/gather");
BENCHMARK(BM_LaneFetch8<true>)->Name("BM_LaneFetch8/loads");

__attribute__((target("avx512f"))) void fetch16(const FetchData& d, benchmark::State& state) {
  __m512i sum = _mm512_setzero_si512();
  for (auto _ : state) {
    for (size_t k = 0; k < d.index.size(); k += 16)
      sum = _mm512_add_epi32(
          sum, _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), 0xffff,
                                           _mm512_loadu_si512(&d.index[k]), d.words.data(), 4));
    benchmark::DoNotOptimize(sum);
  }
}

void BM_LaneFetch16Gather(benchmark::State& state) {
  if (!__builtin_cpu_supports("avx512f")) {
    state.SkipWithError("no AVX-512 on this CPU");
    return;
  }
  const FetchData& d = data();
  fetch16(d, state);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(d.index.size()));
}
BENCHMARK(BM_LaneFetch16Gather)->Name("BM_LaneFetch16/gather");

}  // namespace
}  // namespace imx
#endif
