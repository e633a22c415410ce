#include "intermix/renderer.hpp"

#include "intermix/error.hpp"
#include "methods/cancellable.hpp"
#include "methods/method_table.hpp"
#include "methods/zslab/zslab.hpp"

namespace imx {

struct Renderer::Impl {
  ZslabStageCache full, hybrid;  // zslab, zslab-hybrid: a viewer may switch between them
  uint64_t budget = kDefaultKeptBudget;
  RendererStats stats;
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

Image Renderer::render(const Scene& scene, const RenderOptions& options) {
  const std::string method = resolve_method(scene, options.method).name;
  impl_->stats = {};
  // imx::render refuses a CSG scene for the methods that do not render it.
  const MethodInfo* m = find_method(method);
  if (scene.csg || !m || m->keeps_stages == KeptStages::none) return imx::render(scene, options);
  const bool hybrid = m->keeps_stages == KeptStages::zslab_hybrid;
  ZslabStageCache& cache = hybrid ? impl_->hybrid : impl_->full;
  ZslabStageCache& other = hybrid ? impl_->full : impl_->hybrid;
  // The method in use gets what the other one leaves of the budget, at least half of it.
  if (other.kept_bytes() > impl_->budget / 2) other = {};
  cache.budget_bytes = impl_->budget - other.kept_bytes();
  int spp = options.spp > 0 ? options.spp : scene.render.spp > 0 ? scene.render.spp : 1;
  ZslabStats s;
  Image image;
  try {
    image = render_zslab_cached(scene, spp, cancellable(options), hybrid, cache, &s);
  } catch (...) {
    cache = {};  // a frame stopped midway may have written into kept arrays still listed
    throw;
  }
  const double pixels = static_cast<double>(scene.image.width) * scene.image.height;
  impl_->stats = {s.stages,
                  s.stages_run,
                  s.stream_bytes_per_pixel,
                  s.kept_bytes_per_pixel + static_cast<double>(other.kept_bytes()) / pixels,
                  s.stages_merged,
                  s.recast_unchanged};
  return image;
}

const RendererStats& Renderer::last_stats() const {
  return impl_->stats;
}

void Renderer::set_kept_budget(uint64_t bytes) {
  impl_->budget = bytes;
}

uint64_t Renderer::kept_budget() const {
  return impl_->budget;
}

void Renderer::clear() {
  impl_->full = {};
  impl_->hybrid = {};
}

}  // namespace imx
