// Whole frames of the volume engine on the ct-head example, timed as process CPU time so that
// other load on the machine disturbs the comparison less than wall time would.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {
namespace {

const Scene& ct_head() {
  static Scene scene = [] {
    Scene s = load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "ct-head.json",
                         {"image.width=256", "image.height=256"});
    return s;
  }();
  return scene;
}

// Variant 0: skipping + ERT (the defaults); 1: plain marching; 2: post-classification;
// 3: on-the-fly gradients; 4: block skipping without distance jumps.
void BM_MdvrCtHead(benchmark::State& state) {
  static const char* overrides[][2] = {{nullptr, nullptr},
                                       {"skipping", "none"},
                                       {"classification", "post"},
                                       {"gradients", "on-the-fly"},
                                       {"skipping", "bricks"}};
  Scene scene = ct_head();
  const auto& o = overrides[state.range(0)];
  if (o[0]) {
    std::string key = o[0], value = o[1];
    if (key == "skipping") scene.render.skipping = value;
    if (key == "classification") scene.render.classification = value;
    if (key == "gradients") scene.render.gradients = value;
  }
  if (state.range(0) == 1) scene.render.ert_threshold = 1.0;
  RenderOptions options;
  options.method = "mdvr";
  render(scene, options);  // builds the caches
  for (auto _ : state) benchmark::DoNotOptimize(render(scene, options));
  state.SetLabel(o[0] ? std::string(o[0]) + "=" + o[1] : "defaults");
}
BENCHMARK(BM_MdvrCtHead)
    ->DenseRange(0, 4)
    ->MeasureProcessCPUTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace imx
