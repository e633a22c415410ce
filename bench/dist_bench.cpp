// Distributed compositing's per-pixel work (docs/distributed.md): encoding a range of slab
// arrays into a message and merging a received one by the intermix kernel, on a 512x512 frame
// whose every sample holds `slabs` slabs per side. The model of docs/distributed.md takes its
// merge cost per slab and encode cost per byte from here.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "dist/slab_message.hpp"

namespace imx {
namespace {

constexpr size_t kPixels = 512 * 512;

// Interleaved slabs: side 0 at even, side 1 at odd positions, so the merge really mixes.
ZtBuffer arrays(int slabs, int side, SlabFormat format) {
  ZtBuffer b(kPixels, 8, format);
  std::mt19937 rng(static_cast<uint32_t>(side + 1));
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Slab> list(static_cast<size_t>(slabs));
  for (size_t i = 0; i < kPixels; ++i) {
    for (int k = 0; k < slabs; ++k) {
      float a = 0.02f + 0.1f * u(rng);
      list[static_cast<size_t>(k)] = {10.0f + 4.0f * k + 2.0f * side + 1.0f, 1.0f,
                                      glm::vec4(0.5f * a, 0.3f * a, 0.2f * a, a)};
    }
    b.store(i, list);
  }
  return b;
}

// Args: slabs per sample on each side, format (0: rgba32f, 1: rgba8).
void BM_MergeSlabMessage(benchmark::State& state) {
  const int slabs = static_cast<int>(state.range(0));
  const SlabFormat format = state.range(1) ? SlabFormat::rgba8 : SlabFormat::rgba32f;
  const ZtBuffer mine = arrays(slabs, 0, format);
  const std::vector<std::byte> message =
      encode_slab_message(arrays(slabs, 1, format), {0, kPixels}, 1);
  IntermixSettings mix;
  mix.a_ert = 1.0f;  // no early stop: every slab is merged
  for (auto _ : state) {
    state.PauseTiming();
    ZtBuffer target = mine;
    state.ResumeTiming();
    merge_slab_message(target, {0, kPixels}, 1, message, true, mix, 1);
    benchmark::DoNotOptimize(target);
  }
  const double merged = static_cast<double>(kPixels) * 2.0 * slabs;
  state.counters["ns_per_slab"] = benchmark::Counter(
      merged, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["bytes_per_pixel"] = static_cast<double>(message.size()) / kPixels;
}
BENCHMARK(BM_MergeSlabMessage)
    ->ArgsProduct({{1, 2, 4}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Args: slabs per sample, threads (the ratio of the two thread counts is the encode's speed-up).
void BM_EncodeSlabMessage(benchmark::State& state) {
  const int slabs = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const ZtBuffer b = arrays(slabs, 0, SlabFormat::rgba32f);
  size_t bytes = 0;
  for (auto _ : state) bytes = encode_slab_message(b, {0, kPixels}, 1, threads).size();
  state.counters["ns_per_byte"] =
      benchmark::Counter(static_cast<double>(bytes), benchmark::Counter::kIsIterationInvariantRate |
                                                         benchmark::Counter::kInvert);
}
BENCHMARK(BM_EncodeSlabMessage)
    ->ArgsProduct({{1, 4}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace imx
