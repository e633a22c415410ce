// render(): one frame of a scene with a chosen method.
#pragma once
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "intermix/image.hpp"
#include "intermix/scene.hpp"

namespace imx {

struct RenderOptions {
  std::string method;  // empty: the scene's render.method; "auto": resolve_method's choice
  int spp = 0;         // 0: the scene's, else the method's default
  int threads = 0;     // 0: all cores
  // Called now and then with the finished fraction in [0, 1], from one thread at a time.
  std::function<void(double)> progress;
  // >= 0: only sample `sample_index` of the spp-sample stratified pattern, one per pixel. The
  // mean of the images for every index in [0, spp) is the spp image (progressive refinement).
  int sample_index = -1;
  // When it becomes true, render() stops soon and throws imx::Cancelled (a viewer's new input).
  const std::atomic<bool>* cancel = nullptr;
};

// Names of the methods this build implements.
std::vector<std::string> available_methods();

// The method render() uses for `scene` when asked for `method` (empty: the scene's
// render.method): that name, or for "auto" (the default) the fastest method within reach of
// the best image on the scene's kind of content (src/methods/automatic_method.hpp), with why.
struct ResolvedMethod {
  std::string name;
  std::string reason;  // empty unless chosen by "auto": "volumes only", "a csg block", ...
};
ResolvedMethod resolve_method(const Scene& scene, const std::string& method = "");

// Samples per pixel `method` renders with when neither the scene nor the caller sets them
// (0 for an unknown method).
int default_spp(const std::string& method);

// Renders the scene; the result is premultiplied linear RGBA over the scene's background.
// Throws imx::Error for an unknown method or settings the method cannot use.
Image render(const Scene& scene, const RenderOptions& options = {});

}  // namespace imx
