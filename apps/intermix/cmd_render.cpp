// intermix render SCENE.json -o OUT.png: one frame of a scene file.
#include <chrono>
#include <cstdio>

#include <fmt/format.h>

#include "commands.hpp"
#include "core/parallel.hpp"
#include "core/progress_bar.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx::cli {

Command add_render(CLI::App& app) {
  struct Options {
    std::string scene, output, method;
    int width = 0, height = 0, spp = 0, threads = 0;
    std::vector<std::string> overrides;
    bool linear = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("scene", o->scene, "scene file (JSON)")->required();
  app.add_option("-o,--output", o->output, "output PNG")->required();
  app.add_option("--method", o->method, "rendering method (default: the scene's, else reference)");
  app.add_option("--width", o->width, "image width in pixels (overrides the scene)")
      ->check(in_range(1, kMaxImageSide));
  app.add_option("--height", o->height, "image height in pixels (overrides the scene)")
      ->check(in_range(1, kMaxImageSide));
  app.add_option("--spp", o->spp, "samples per pixel, a perfect square (1, 4, 16, 64, ...)")
      ->check(in_range(1, kMaxSpp));
  app.add_option("--threads", o->threads, "worker threads (default: all cores)")
      ->check(in_range(0, kMaxThreads));
  app.add_option("--set", o->overrides, "override a scene value: key.path=value (repeatable)");
  app.add_flag("--linear", o->linear, "write linear instead of sRGB-encoded colour");
  return [o]() {
    std::vector<std::string> overrides = o->overrides;
    if (o->width > 0) overrides.push_back(fmt::format("image.width={}", o->width));
    if (o->height > 0) overrides.push_back(fmt::format("image.height={}", o->height));
    Scene scene = load_scene(o->scene, overrides);
    print_notes(scene.notes);
    RenderOptions options;
    options.method = o->method;
    options.spp = o->spp;
    options.threads = o->threads;
    ProgressBar bar("render", show_progress());
    options.progress = [&bar](double f) { bar.update(f); };
    auto start = std::chrono::steady_clock::now();
    Image image;
    try {
      image = render(scene, options);
    } catch (const Error& e) {
      throw Error(fmt::format("{}: {}", o->scene, e.what()));  // what the method refused
    }
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    bar.finish();
    write_png(image, o->output, o->linear);
    std::string method = o->method.empty() ? scene.render.method : o->method;
    if (!quiet())
      std::fprintf(stderr, "intermix: %s: %dx%d with %s on %d threads in %.3f s -> %s\n",
                   o->scene.c_str(), image.width(), image.height(), method.c_str(),
                   resolve_thread_count(o->threads), seconds, o->output.c_str());
    return 0;
  };
}

}  // namespace imx::cli
