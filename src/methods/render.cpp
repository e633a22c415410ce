#include "intermix/render.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "methods/cancellable.hpp"
#include "methods/csg.hpp"
#include "methods/dfb.hpp"
#include "methods/kbuffer.hpp"
#include "methods/mdvr.hpp"
#include "methods/oit.hpp"
#include "methods/peel.hpp"
#include "methods/reference.hpp"
#include "methods/zslab.hpp"

namespace imx {

namespace {

// Every method of this build: its name, its samples per pixel when neither the scene nor the
// caller sets them, its entry point, and whether it renders a scene's csg block and exclusive
// mixing. One line per method.
struct MethodEntry {
  const char* name;
  int default_spp;
  Image (*render)(const Scene&, int spp, const RenderOptions&);
  bool renders_csg = false;
};

constexpr MethodEntry kMethods[] = {
    {"reference", kReferenceDefaultSpp, render_reference, true},
    {"csg", 1, render_csg, true},
    {"mdvr", 1, render_mdvr},
    {"zslab", 1, render_zslab},
    {"zslab-hybrid", 1, render_zslab_hybrid},
    {"peel", 1, render_peel},
    {"dfb", 1, render_dfb},
    {"dfb-sfm", 1, render_dfb_sfm},
    {"kbuffer", 1, render_kbuffer},
    {"kbuffer-ofm", 1, render_kbuffer_ofm},
    {"wboit", 1, render_wboit},
    {"mboit", 1, render_mboit},
};

}  // namespace

std::vector<std::string> available_methods() {
  std::vector<std::string> names;
  for (const MethodEntry& m : kMethods) names.emplace_back(m.name);
  return names;
}

int default_spp(const std::string& method) {
  for (const MethodEntry& m : kMethods)
    if (method == m.name) return m.default_spp;
  return 0;
}

Image render(const Scene& scene, const RenderOptions& options) {
  const std::string method = options.method.empty() ? scene.render.method : options.method;
  int spp = options.spp > 0 ? options.spp : scene.render.spp;
  // The image and its per-tile sample buffers; kept stage outputs are checked where they are.
  check_memory(uint64_t{2} * static_cast<uint64_t>(scene.image.width) *
                   static_cast<uint64_t>(scene.image.height) * sizeof(glm::vec4),
               fmt::format("a {}x{} image", scene.image.width, scene.image.height));
  for (const MethodEntry& m : kMethods) {
    if (method != m.name) continue;
    if (scene.csg && !m.renders_csg)
      throw Error(fmt::format(
          "method '{}' does not render CSG (the scene has a csg block); use csg or reference, "
          "or --set csg=null",
          method));
    if (scene.render.mixing == "exclusive" && !m.renders_csg)
      throw Error(fmt::format(
          "method '{}' mixes volumes inclusively only (render.mixing is exclusive); use csg or "
          "reference, or --set render.mixing=inclusive",
          method));
    return m.render(scene, spp > 0 ? spp : m.default_spp, cancellable(options));
  }
  throw Error(fmt::format("method '{}' is not available; this build has: {}", method,
                          fmt::join(available_methods(), ", ")));
}

}  // namespace imx
