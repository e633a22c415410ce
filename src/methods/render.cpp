#include "intermix/render.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "methods/automatic_method.hpp"
#include "methods/cancellable.hpp"
#include "methods/csg/csg.hpp"
#include "methods/fragment/dfb.hpp"
#include "methods/fragment/kbuffer.hpp"
#include "methods/fragment/oit.hpp"
#include "methods/fragment/peel.hpp"
#include "methods/mdvr/mdvr.hpp"
#include "methods/method_table.hpp"
#include "methods/reference/reference.hpp"
#include "methods/zslab/zslab.hpp"

namespace imx {

namespace {

// Every method of this build, one line each: its name, its samples per pixel when neither the
// scene nor the caller sets them, its entry point, and what other code asks of it
// (method_table.hpp).
//  name, default spp, entry, renders CSG, keeps stages, distributable
constexpr MethodInfo kMethods[] = {
    {"reference", kReferenceDefaultSpp, render_reference, true},
    {"csg", 1, render_csg, true},
    {"mdvr", 1, render_mdvr},
    {"zslab", 1, render_zslab, false, KeptStages::zslab, true},
    {"zslab-hybrid", 1, render_zslab_hybrid, false, KeptStages::zslab_hybrid, true},
    {"peel", 1, render_peel},
    {"dfb", 1, render_dfb},
    {"dfb-sfm", 1, render_dfb_sfm},
    {"kbuffer", 1, render_kbuffer},
    {"kbuffer-ofm", 1, render_kbuffer_ofm},
    {"wboit", 1, render_wboit},
    {"mboit", 1, render_mboit},
};

}  // namespace

std::span<const MethodInfo> method_table() {
  return kMethods;
}

const MethodInfo* find_method(std::string_view name) {
  for (const MethodInfo& m : kMethods)
    if (name == m.name) return &m;
  return nullptr;
}

std::vector<std::string> available_methods() {
  std::vector<std::string> names;
  for (const MethodInfo& m : kMethods) names.emplace_back(m.name);
  return names;
}

int default_spp(const std::string& method) {
  const MethodInfo* m = find_method(method);
  return m ? m->default_spp : 0;
}

ResolvedMethod resolve_method(const Scene& scene, const std::string& method) {
  const std::string& asked = method.empty() ? scene.render.method : method;
  if (asked != "auto") return {asked, ""};
  MethodChoice choice = choose_method(scene);
  return {std::move(choice.method), std::move(choice.reason)};
}

Image render(const Scene& scene, const RenderOptions& options) {
  const std::string method = resolve_method(scene, options.method).name;
  int spp = options.spp > 0 ? options.spp : scene.render.spp;
  // The image and its per-tile sample buffers; kept stage outputs are checked where they are.
  check_memory(uint64_t{2} * static_cast<uint64_t>(scene.image.width) *
                   static_cast<uint64_t>(scene.image.height) * sizeof(glm::vec4),
               fmt::format("a {}x{} image", scene.image.width, scene.image.height));
  if (const MethodInfo* m = find_method(method)) {
    if (scene.csg && !m->renders_csg)
      throw Error(fmt::format(
          "method '{}' does not render CSG (the scene has a csg block); use csg or reference, "
          "or --set csg=null",
          method));
    if (scene.render.mixing == "exclusive" && !m->renders_csg)
      throw Error(fmt::format(
          "method '{}' mixes volumes inclusively only (render.mixing is exclusive); use csg or "
          "reference, or --set render.mixing=inclusive",
          method));
    return m->render(scene, spp > 0 ? spp : m->default_spp, cancellable(options));
  }
  throw Error(fmt::format("method '{}' is not available; this build has: auto, {}", method,
                          fmt::join(available_methods(), ", ")));
}

}  // namespace imx
