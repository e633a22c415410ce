// Transfer functions: the first byte picks (mod 3) a Slicer .vp file, a ParaView colour-map .json
// or a scene file's "transfer_function" object (points, presets, the colour-map form with range,
// threshold and symmetric), the rest is the text. An accepted one must give sorted, finite points
// in [0, 1] that a renderer's lookup table takes.
#include <cmath>
#include <cstdlib>
#include <exception>

#include "harness.hpp"
#include "intermix/error.hpp"
#include "presets/paraview_colormap.hpp"
#include "presets/slicer_volume_property.hpp"
#include "presets/vp_file.hpp"
#include "scene/scene_parsers.hpp"
#include "volume/tf_lut.hpp"

namespace {

void check_points(const imx::TransferFunction& tf) {
  for (size_t i = 0; i < tf.points.size(); ++i) {
    const imx::TfPoint& p = tf.points[i];
    bool ok = std::isfinite(p.value) && (i == 0 || tf.points[i - 1].value <= p.value);
    for (int c = 0; c < 4; ++c) ok = ok && p.rgba[c] >= 0.0f && p.rgba[c] <= 1.0f;
    if (!ok) std::abort();  // a reader let through what the renderer would misread
  }
  try {
    imx::TfLut lut(tf);
  } catch (const imx::Error&) {
    std::abort();  // accepted by the parser, refused by the renderer
  }
}

// A scene's "transfer_function" object, read as load_scene reads it ("file" in the scratch dir).
imx::TransferFunction scene_transfer_function(const uint8_t* data, size_t size,
                                              const std::filesystem::path& dir) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const nlohmann::json json = imx::scene_json::parse_scene_json(text, "fuzz");
  imx::scene_json::SceneContext context;
  context.base_dir = dir;
  const imx::scene_json::JsonReader r(json, "fuzz", "transfer_function");
  return imx::scene_json::parse_transfer_function(r, context).transfer_function;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  if (size < 1) return 0;
  const ScratchDir& dir = scratch();
  dir.clear();
  const int mode = data[0] % 3;
  if (mode == 2) {
    try {
      check_points(scene_transfer_function(data + 1, size - 1, dir.path()));
      accepted("scene");
    } catch (const std::exception& e) {
      refused(e);
    }
    return 0;
  }
  const bool vp = mode == 0;
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
