// The CSG pieces on their own: the per-ray interval classifier on synthetic rows, and whole csg
// frames of the cutaway example against the same frame without its csg block.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <vector>

#include "csg/ray_intervals.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {
namespace {

// A row of n nested mesh shells (front faces, then back faces) and the union of all of them.
void BM_ClassifyNestedShells(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  std::vector<ClipState> states;
  std::vector<int8_t> primitive_of_object;
  std::vector<Fragment> row;
  for (int k = 0; k < n; ++k) {
    states.push_back({PrimitiveMask{1} << k, 0});
    primitive_of_object.push_back(static_cast<int8_t>(k));
  }
  for (int k = 0; k < n; ++k) row.push_back({10.0f + k, glm::vec4(0.1f), uint32_t(k), 1});
  for (int k = n - 1; k >= 0; --k) row.push_back({50.0f - k, glm::vec4(0.1f), uint32_t(k), 0});
  CsgView view;
  view.states = states;
  view.primitive_of_object = primitive_of_object;
  view.geometric = view.meshes = view.used = low_primitives(n);
  view.primitive_count = n;
  std::vector<Fragment> surfaces(row.size());
  std::vector<CsgRange> ranges(csg_range_capacity(row.size()));
  const std::vector<CsgVolumeSpan> spans(n, CsgVolumeSpan{});
  for (auto _ : state) {
    CsgIntervals r = classify_csg_ray(
        row, view, spans, [](int, float) { return true; }, surfaces, ranges);
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(row.size()));
}
BENCHMARK(BM_ClassifyNestedShells)->Arg(1)->Arg(4)->Arg(16);

// Variant 0: the cutaway example as it is (csg); 1: the same file with csg=null (mdvr).
void BM_CsgCutaway(benchmark::State& state) {
  std::vector<std::string> overrides = {"image.width=256", "image.height=256"};
  if (state.range(0) == 1) overrides.push_back("csg=null");
  const Scene scene =
      load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "csg-cutaway.json", overrides);
  RenderOptions options;
  options.method = "csg";
  render(scene, options);  // builds the caches
  for (auto _ : state) benchmark::DoNotOptimize(render(scene, options));
  state.SetLabel(state.range(0) == 1 ? "csg=null" : "csg");
}
BENCHMARK(BM_CsgCutaway)->DenseRange(0, 1)->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace imx
