// intermix bench SCENE: ms per frame of one or more methods on one scene, in one run.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "core/progress_bar.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx::cli {

namespace {

// The camera turned about the target's vertical by `degrees`, so each frame is really rendered.
Camera jittered(const Camera& camera, double degrees) {
  glm::dmat4 turn = glm::rotate(glm::dmat4(1.0), glm::radians(degrees), camera.up);
  Camera c = camera;
  c.eye = camera.target + glm::dvec3(turn * glm::dvec4(camera.eye - camera.target, 0.0));
  return c;
}

double peak_resident_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

}  // namespace

Command add_bench(CLI::App& app) {
  struct Options {
    std::string scene;
    std::vector<std::string> methods, overrides;
    int frames = 5, width = 0, height = 0, spp = 0, threads = 0;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("scene", o->scene, "scene file (JSON)")->required();
  app.add_option("--method", o->methods, "method to time (repeatable; default: the scene's)");
  app.add_option("--frames", o->frames, "timed frames after one warm-up frame")
      ->check(CLI::PositiveNumber);
  app.add_option("--width", o->width, "image width")->check(CLI::PositiveNumber);
  app.add_option("--height", o->height, "image height")->check(CLI::PositiveNumber);
  app.add_option("--spp", o->spp, "samples per pixel")->check(CLI::PositiveNumber);
  app.add_option("--threads", o->threads, "worker threads (default: all cores)");
  app.add_option("--set", o->overrides, "override a scene value: key.path=value (repeatable)");
  app.add_flag("--json", o->json, "print one JSON object on stdout");
  return [o]() {
    std::vector<std::string> overrides = o->overrides;
    if (o->width > 0) overrides.push_back(fmt::format("image.width={}", o->width));
    if (o->height > 0) overrides.push_back(fmt::format("image.height={}", o->height));
    Scene scene = load_scene(o->scene, overrides);
    std::vector<std::string> methods = o->methods;
    if (methods.empty()) methods.push_back(scene.render.method);
    nlohmann::json results = nlohmann::json::array();
    for (const std::string& method : methods) {
      RenderOptions options;
      options.method = method;
      options.spp = o->spp;
      options.threads = o->threads;
      ProgressBar bar(fmt::format("bench {}", method), show_progress());
      render(scene, options);  // warm-up: caches, page faults, thread pool
      std::vector<double> ms;
      for (int f = 0; f < o->frames; ++f) {
        Scene frame = scene;
        frame.camera = jittered(scene.camera, f % 2 == 0 ? 0.5 : -0.5);
        auto start = std::chrono::steady_clock::now();
        render(frame, options);
        ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count());
        bar.update(static_cast<double>(f + 1) / o->frames);
      }
      bar.finish();
      std::vector<double> sorted = ms;
      std::sort(sorted.begin(), sorted.end());
      double median = sorted.size() % 2
                          ? sorted[sorted.size() / 2]
                          : 0.5 * (sorted[sorted.size() / 2 - 1] + sorted[sorted.size() / 2]);
      int spp = o->spp > 0 ? o->spp : scene.render.spp;
      double rays = static_cast<double>(scene.image.width) * scene.image.height * std::max(spp, 1);
      results.push_back({{"method", method},
                         {"frames", o->frames},
                         {"ms_median", median},
                         {"ms_min", sorted.front()},
                         {"ms_max", sorted.back()},
                         {"rays_per_s", spp > 0 ? nlohmann::json(rays / (median / 1000.0))
                                                : nlohmann::json(nullptr)},
                         {"peak_rss_mib", peak_resident_mib()}});
    }
    if (o->json) {
      nlohmann::json out = {{"scene", o->scene},
                            {"width", scene.image.width},
                            {"height", scene.image.height},
                            {"methods", results}};
      std::printf("%s\n", out.dump().c_str());
    } else {
      std::printf("%s at %dx%d\n", o->scene.c_str(), scene.image.width, scene.image.height);
      double first = results.front()["ms_median"];
      for (const auto& r : results)
        std::printf("  %-16s median %9.1f ms  min %9.1f  max %9.1f  (x%.2f of %s)  peak %.0f MiB\n",
                    r["method"].get<std::string>().c_str(), r["ms_median"].get<double>(),
                    r["ms_min"].get<double>(), r["ms_max"].get<double>(),
                    r["ms_median"].get<double>() / first, methods.front().c_str(),
                    r["peak_rss_mib"].get<double>());
    }
    return 0;
  };
}

}  // namespace imx::cli
