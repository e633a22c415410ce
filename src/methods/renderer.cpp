#include "intermix/renderer.hpp"

#include "methods/zslab.hpp"

namespace imx {

struct Renderer::Impl {
  ZslabStageCache zslab;
  std::string zslab_method;  // the method the cache was filled by
  RendererStats stats;
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

Image Renderer::render(const Scene& scene, const RenderOptions& options) {
  const std::string method = options.method.empty() ? scene.render.method : options.method;
  impl_->stats = {};
  // imx::render refuses a CSG scene for the methods that do not render it.
  if (scene.csg || (method != "zslab" && method != "zslab-hybrid"))
    return imx::render(scene, options);
  if (impl_->zslab_method != method) impl_->zslab = {};
  impl_->zslab_method = method;
  int spp = options.spp > 0 ? options.spp : scene.render.spp > 0 ? scene.render.spp : 1;
  ZslabStats s;
  Image image =
      render_zslab_cached(scene, spp, options, method == "zslab-hybrid", impl_->zslab, &s);
  impl_->stats = {s.stages, s.stages_run, s.stream_bytes_per_pixel, s.kept_bytes_per_pixel};
  return image;
}

const RendererStats& Renderer::last_stats() const {
  return impl_->stats;
}

void Renderer::clear() {
  impl_->zslab = {};
  impl_->zslab_method.clear();
}

}  // namespace imx
