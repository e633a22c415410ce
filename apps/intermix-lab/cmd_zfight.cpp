// intermix zfight SCENE: the z-fighting metric (SPEC §9) of one or more methods on a scene.
#include <cstdio>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/parallel.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "lab_commands.hpp"
#include "probes/z_fighting_probe.hpp"

namespace imx::cli {

Command add_zfight(CLI::App& app) {
  struct Options : SceneOptions {
    std::string scene;
    std::vector<std::string> methods;
    std::vector<double> jitter{0.37, 0.21};
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("scene", o->scene, "scene file (JSON) with coplanar surfaces")->required();
  app.add_option("--method", o->methods, "method to measure (repeatable; default: the scene's)");
  add_scene_options(app, *o, kSizeOption | kSppOption | kThreadsOption);
  app.add_option("--jitter", o->jitter, "camera shift in pixels, x y (default 0.37 0.21)")
      ->expected(2);
  add_scene_options(app, *o, kSetOption);
  app.add_flag("--json", o->json, "print one JSON object on stdout");
  return [o]() {
    const std::vector<std::string> overrides = o->with_size();
    Scene scene = load_scene(o->scene, overrides);
    std::vector<std::string> methods = o->methods;
    if (methods.empty()) methods.push_back(scene.render.method);
    nlohmann::json results = nlohmann::json::array();
    for (const std::string& method : methods) {
      RenderOptions options;
      options.method = method;
      options.spp = o->spp;
      options.threads = o->threads;
      ZFightingStats s = measure_z_fighting(scene, options, {o->jitter[0], o->jitter[1]});
      results.push_back({{"method", method},
                         {"pixels", s.pixels},
                         {"std_dev", s.std_dev},
                         {"speckle", s.speckle},
                         {"jittered_std_dev", s.jittered_std_dev},
                         {"jitter_change", s.jitter_change}});
    }
    if (o->json) {
      std::printf("%s\n", nlohmann::json{{"scene", o->scene}, {"methods", results}}.dump().c_str());
      return 0;
    }
    std::printf("%s: coplanar region of %ld pixels; values x255 (display levels)\n",
                o->scene.c_str(), results.front()["pixels"].get<long>());
    for (const auto& r : results)
      std::printf("  %-12s std dev %7.3f  speckle %7.3f  jittered std dev %7.3f  change %7.3f\n",
                  r["method"].get<std::string>().c_str(), 255.0 * r["std_dev"].get<double>(),
                  255.0 * r["speckle"].get<double>(), 255.0 * r["jittered_std_dev"].get<double>(),
                  255.0 * r["jitter_change"].get<double>());
    return 0;
  };
}

}  // namespace imx::cli
