#include "intermix/render.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "intermix/error.hpp"
#include "methods/mdvr.hpp"
#include "methods/reference.hpp"

namespace imx {

std::vector<std::string> available_methods() {
  return {"reference", "mdvr"};
}

Image render(const Scene& scene, const RenderOptions& options) {
  const std::string method = options.method.empty() ? scene.render.method : options.method;
  int spp = options.spp > 0 ? options.spp : scene.render.spp;
  if (method == "reference")
    return render_reference(scene, spp > 0 ? spp : kReferenceDefaultSpp, options);
  if (method == "mdvr") return render_mdvr(scene, spp > 0 ? spp : 1, options);
  throw Error(fmt::format("method '{}' is not available; this build has: {}", method,
                          fmt::join(available_methods(), ", ")));
}

}  // namespace imx
