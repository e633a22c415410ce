// Cancellation for a viewer: render() polls RenderOptions::cancel where it reports progress (after
// each tile), so kernels stay pure and an abandoned frame stops within one tile per thread.
#pragma once
#include "intermix/error.hpp"
#include "intermix/render.hpp"

namespace imx {

// `options` with its progress callback wrapped to throw imx::Cancelled once *cancel is set;
// throws at once when it already is.
inline RenderOptions cancellable(const RenderOptions& options) {
  if (!options.cancel) return options;
  if (options.cancel->load(std::memory_order_relaxed)) throw Cancelled();
  RenderOptions out = options;
  out.progress = [cancel = options.cancel, progress = options.progress](double fraction) {
    if (cancel->load(std::memory_order_relaxed)) throw Cancelled();
    if (progress) progress(fraction);
  };
  return out;
}

}  // namespace imx
