// The per-sample settings of a zSlab pipeline and the largest arrays it holds (SPEC §4): what the
// kernels, the ZT-buffers and a distributed merge of slab arrays all size themselves by.
#pragma once
#include "slab/intermix_kernel.hpp"

namespace imx {

// RenderSettings::kMaxLayers (asserted where the settings are read: methods/zslab/zslab_kernel.hpp).
inline constexpr int kMaxZslabLayers = 16;  // the largest N (ZT slabs)
inline constexpr int kMaxRtLayers = 16;     // the largest M (RT layers)

// Per-sample settings of a zSlab pipeline.
struct ZslabParams {
  IntermixSettings mix;  // interpolation, ERT, overflow of a full ZT array
  int layers = 8;        // N
  int rt_layers = 4;     // M
  int peel_layers = 4;   // L
};

}  // namespace imx
