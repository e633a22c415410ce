#include "intermix/render.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "intermix/error.hpp"
#include "methods/mdvr.hpp"
#include "methods/reference.hpp"

namespace imx {

namespace {

// Every method of this build: its name, its samples per pixel when neither the scene nor the
// caller sets them, and its entry point. One line per method.
struct MethodEntry {
  const char* name;
  int default_spp;
  Image (*render)(const Scene&, int spp, const RenderOptions&);
};

constexpr MethodEntry kMethods[] = {
    {"reference", kReferenceDefaultSpp, render_reference},
    {"mdvr", 1, render_mdvr},
};

}  // namespace

std::vector<std::string> available_methods() {
  std::vector<std::string> names;
  for (const MethodEntry& m : kMethods) names.emplace_back(m.name);
  return names;
}

Image render(const Scene& scene, const RenderOptions& options) {
  const std::string method = options.method.empty() ? scene.render.method : options.method;
  int spp = options.spp > 0 ? options.spp : scene.render.spp;
  for (const MethodEntry& m : kMethods)
    if (method == m.name) return m.render(scene, spp > 0 ? spp : m.default_spp, options);
  throw Error(fmt::format("method '{}' is not available; this build has: {}", method,
                          fmt::join(available_methods(), ", ")));
}

}  // namespace imx
