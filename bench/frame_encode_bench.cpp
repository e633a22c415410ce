// Encoding one viewer frame (docs/viewer.md): JPEG while the user moves, PNG once still. The
// frame is ct-implant rendered once at 512x512 (zslab, 1 spp), so the encoders see real image
// content, not noise or flat colour.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <string>

#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "server/jpeg_encoder.hpp"

namespace imx {
namespace {

const Image& frame(int side) {
  static std::map<int, Image> frames;
  auto it = frames.find(side);
  if (it != frames.end()) return it->second;
  const Scene scene =
      load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "ct-implant.json",
                 {"image.width=" + std::to_string(side), "image.height=" + std::to_string(side)});
  RenderOptions options;
  options.method = "zslab";
  options.spp = 1;
  return frames.emplace(side, render(scene, options)).first->second;
}

void BM_EncodeJpeg(benchmark::State& state) {
  const Image& image = frame(static_cast<int>(state.range(0)));
  size_t bytes = 0;
  for (auto _ : state) bytes = server::encode_jpeg(image, 85).size();
  state.counters["KiB"] = static_cast<double>(bytes) / 1024.0;
}
BENCHMARK(BM_EncodeJpeg)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond)->UseRealTime();

// Arg 1: zlib level (-1: spng's default, 6).
void BM_EncodePng(benchmark::State& state) {
  const Image& image = frame(static_cast<int>(state.range(0)));
  size_t bytes = 0;
  for (auto _ : state)
    bytes = encode_png(image, "frame", false, static_cast<int>(state.range(1))).size();
  state.counters["KiB"] = static_cast<double>(bytes) / 1024.0;
}
BENCHMARK(BM_EncodePng)
    ->Args({512, 1})
    ->Args({512, -1})
    ->Args({256, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace imx
