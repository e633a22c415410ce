// Renders a scene twice with one imx::Renderer: between the frames the first volume's transfer
// function fades to half its opacity, and zslab renders only that volume's stage again.
//   render_twice SCENE.json OUT.png [key=value...]   (overrides, as intermix render --set)
#include <chrono>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <intermix/error.hpp>
#include <intermix/io.hpp>
#include <intermix/renderer.hpp>
#include <intermix/scene.hpp>

int main(int argc, char** argv) try {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s SCENE.json OUT.png [key=value...]\n", argv[0]);
    return 2;
  }
  imx::Scene scene = imx::load_scene(argv[1], std::vector<std::string>(argv + 3, argv + argc));
  if (scene.volumes.empty()) throw imx::Error(std::string(argv[1]) + ": no volume to change");
  imx::Renderer renderer;
  imx::RenderOptions options;
  options.method = "zslab";  // keeps each object's slab array from frame to frame
  auto frame = [&](const char* label) {
    const auto start = std::chrono::steady_clock::now();
    imx::Image image = renderer.render(scene, options);
    const std::chrono::duration<double, std::milli> ms = std::chrono::steady_clock::now() - start;
    const imx::RendererStats& stats = renderer.last_stats();
    std::printf("%s: %dx%d in %.1f ms, stages %d, stages_run %d\n", label, image.width(),
                image.height(), ms.count(), stats.stages, stats.stages_run);
    return image;
  };
  frame("first");
  for (imx::TfPoint& point : scene.volumes[0].transfer_function.points) point.rgba.a *= 0.5f;
  imx::write_png(frame("second"), argv[2]);
  std::printf("wrote %s\n", argv[2]);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "render_twice: %s\n", e.what());
  return 1;
}
