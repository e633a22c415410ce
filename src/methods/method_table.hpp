// The method table (src/methods/render.cpp): every method of this build with what other code
// asks of it by name, so that no code outside the table compares method names.
#pragma once
#include <cstdint>
#include <span>
#include <string_view>

#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {

// Whose stage outputs imx::Renderer keeps between frames (object-level reuse): none, or the
// zSlab pipeline's, fully deferred or with its last volume cast on the fly.
enum class KeptStages : uint8_t { none, zslab, zslab_hybrid };

struct MethodInfo {
  const char* name;
  int default_spp;  // when neither the scene nor the caller sets spp
  Image (*render)(const Scene&, int spp, const RenderOptions&);
  bool renders_csg = false;  // a scene's csg block and exclusive mixing
  KeptStages keeps_stages = KeptStages::none;
  bool distributable = false;  // --distributed: ranks render zSlab arrays, composited by swap
};

// Every method, in the order available_methods() names them.
std::span<const MethodInfo> method_table();

// The method called `name`; null when this build has none.
const MethodInfo* find_method(std::string_view name);

}  // namespace imx
