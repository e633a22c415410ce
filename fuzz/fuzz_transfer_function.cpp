// Transfer-function files: the first byte picks a Slicer .vp file or a ParaView colour-map
// .json, the rest is the file. An accepted file must give sorted, finite points in [0, 1].
#include <cmath>
#include <cstdlib>
#include <exception>

#include "harness.hpp"
#include "presets/paraview_colormap.hpp"
#include "presets/slicer_volume_property.hpp"
#include "presets/vp_file.hpp"

namespace {

void check_points(const imx::TransferFunction& tf) {
  for (size_t i = 0; i < tf.points.size(); ++i) {
    const imx::TfPoint& p = tf.points[i];
    bool ok = std::isfinite(p.value) && (i == 0 || tf.points[i - 1].value <= p.value);
    for (int c = 0; c < 4; ++c) ok = ok && p.rgba[c] >= 0.0f && p.rgba[c] <= 1.0f;
    if (!ok) std::abort();  // a reader let through what the renderer would misread
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  if (size < 1) return 0;
  const ScratchDir& dir = scratch();
  dir.clear();
  const bool vp = data[0] % 2 == 0;
  std::filesystem::path file = dir.write(vp ? "in.vp" : "in.json", data + 1, size - 1);
  try {
    if (vp)
      check_points(imx::to_transfer_function(imx::read_vp_file(file)));
    else
      check_points(imx::read_paraview_colormap(file, "").transfer_function);
    accepted(vp ? "vp" : "paraview");
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
