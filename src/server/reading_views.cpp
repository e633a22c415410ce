#include "server/reading_views.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "core/colour.hpp"
#include "frame/slice_view.hpp"
#include "intermix/io.hpp"
#include "scene/json_reader.hpp"
#include "scene/label_map_parser.hpp"
#include "scene/scene_parsers.hpp"
#include "server/jpeg_encoder.hpp"
#include "server/slice_orientation.hpp"
#include "server/streamline_slab.hpp"

namespace imx::server {
namespace {

using Json = nlohmann::json;
using scene_json::JsonReader;
using scene_json::Range;

constexpr int kMaxViewSide = 2048;       // a quadrant of a 4K screen at devicePixelRatio 1
constexpr int kMovingSliceQuality = 90;  // a 2-D view's JPEG while its window or pan is dragged

Json vec_json(const glm::dvec3& v) {
  return Json::array({v.x, v.y, v.z});
}

// The volumes and meshes the session shows (visible), in scene order.
std::vector<int> shown_volumes(const ViewerState& state) {
  std::vector<int> shown;
  const Scene& scene = state.scene();
  for (size_t k = 0; k < scene.order.size(); ++k)
    if (scene.order[k].kind == ObjectKind::volume &&
        (k >= state.visible.size() || state.visible[k]))
      shown.push_back(scene.order[k].index);
  return shown;
}

}  // namespace

SliceAnswer answer_slice(const ViewerState& state, const Json& message) {
  const JsonReader r(message, "slice");
  r.check_keys({"type", "seq", "view", "point", "width", "height", "mm_per_pixel", "window", "slab",
                "format", "rotation", "thick_slab"});
  const JsonReader axis_reader = r.get("view");
  const SliceAxis axis = *find_slice_axis(axis_reader.choice({"axial", "coronal", "sagittal"}));
  const glm::dvec3 point = r.get("point").vec3(Range::coordinate());
  const int width = r.get("width").integer(1, kMaxViewSide);
  const int height = r.get("height").integer(1, kMaxViewSide);
  const double mm = r.get("mm_per_pixel").number(Range::length());
  // JPEG while a drag goes on (a quarter of PNG's encoding time), PNG when it stops.
  const bool jpeg = r.has("format") && r.get("format").choice({"png", "jpeg"}) == "jpeg";
  // An oblique view (the crosshair's rotation) and a thick slab's projection, both optional.
  const glm::dmat3 rotation = r.has("rotation") ? parse_rotation(r.get("rotation")) : glm::dmat3(1);
  SliceView view = slice_view(axis, point, width, height, mm, rotation);
  if (auto s = r.find("thick_slab")) view.slab = scene_json::parse_slab(*s);
  const Scene& scene = state.scene();
  const std::vector<int> shown = shown_volumes(state);
  std::vector<glm::dvec2> window_of(scene.volumes.size(), glm::dvec2(0.0, 1.0));
  for (int i : shown)
    window_of[static_cast<size_t>(i)] = volume_window(state, static_cast<size_t>(i));
  if (auto w = r.find("window"); w && !shown.empty()) {
    // The base volume's window while a W/L drag goes on (the edit on release keeps it).
    const glm::dvec2 cw = w->vec2();
    if (!(cw.y > 0.0)) w->at(1).fail(fmt::format("window width {} must be > 0", cw.y));
    window_of[static_cast<size_t>(shown.front())] = cw;
  }
  using Clock = std::chrono::steady_clock;
  const auto ms_since = [](Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
  };
  const Clock::time_point t_render = Clock::now();
  Image image = render_slice(scene, view, shown, window_of);
  // The shown streamlines within the slab around the plane, over the slice (mrview's way).
  const double slab =
      r.has("slab") ? r.get("slab").number(Range::closed(0.01, 1000.0)) : kDefaultStreamlineSlab;
  const int line_px = std::max(1, static_cast<int>(std::lround(std::min(width, height) / 400.0)));
  for (size_t k = 0; k < scene.order.size(); ++k)
    if (scene.order[k].kind == ObjectKind::streamlines &&
        (k >= state.visible.size() || state.visible[k]))
      draw_streamline_slab(
          image, view, scene.streamlines[static_cast<size_t>(scene.order[k].index)], slab, line_px);

  Json outlines = Json::array();
  for (size_t k = 0; k < scene.order.size(); ++k) {
    if (scene.order[k].kind != ObjectKind::mesh || (k < state.visible.size() && !state.visible[k]))
      continue;
    const MeshObject& m = scene.meshes[static_cast<size_t>(scene.order[k].index)];
    Json segments = Json::array();
    for (const glm::dvec4& s : mesh_outline(*m.mesh, view))
      segments.push_back(Json::array({std::round(s.x * 100) / 100, std::round(s.y * 100) / 100,
                                      std::round(s.z * 100) / 100, std::round(s.w * 100) / 100}));
    if (segments.empty()) continue;
    const glm::vec3 c = linear_to_display(m.material.color);  // the page strokes display colours
    outlines.push_back({{"name", m.name},
                        {"color", Json::array({c.r, c.g, c.b})},
                        {"segments", std::move(segments)}});
  }
  Json text = {{"type", "slice"},
               {"view", slice_axis_name(axis)},
               {"point", vec_json(point)},
               {"mm_per_pixel", mm},
               {"slab", slab},
               {"right", vec_json(view.right / mm)},
               {"down", vec_json(view.down / mm)},
               {"normal", vec_json(view.normal)},
               {"thick_slab", scene_json::slab_json(view.slab)},
               {"width", width},
               {"height", height},
               {"outlines", std::move(outlines)}};
  if (message.contains("seq")) text["seq"] = message["seq"];
  text["render_ms"] = std::round(ms_since(t_render) * 100) / 100;
  // Linear like a render, so the PNG's sRGB is what `render` writes for the same plane.
  const Clock::time_point t_encode = Clock::now();
  std::string encoded =
      jpeg ? encode_jpeg(image, kMovingSliceQuality) : encode_png(image, "slice", false, 1);
  text["encode_ms"] = std::round(ms_since(t_encode) * 100) / 100;
  text["format"] = jpeg ? "jpeg" : "png";
  return {text.dump(), std::move(encoded)};
}

Json answer_probe(const ViewerState& state, const Json& message) {
  const JsonReader r(message, "probe");
  r.check_keys({"type", "seq", "point"});
  const glm::dvec3 point = r.get("point").vec3(Range::coordinate());
  Json values = Json::array();
  for (const VolumeObject& v : state.scene().volumes) {
    Json entry = {{"name", v.name}, {"units", v.units}, {"value", nullptr}};
    if (const std::optional<VoxelValue> at = voxel_at(v, point)) {
      entry["index"] = Json::array({at->index.x, at->index.y, at->index.z});
      if (std::isfinite(at->value)) entry["value"] = at->value;
      // The trilinear sample there, as an (oblique) view's pixel samples it.
      if (const std::optional<double> s = sample_at(v, point); s && std::isfinite(*s))
        entry["sample"] = *s;
      // A label map's value under the crosshair by its name (its table's, else "label N").
      if (v.labels && std::isfinite(at->value) && at->value == std::floor(at->value) &&
          std::abs(at->value) < 2147483647.0) {
        const LabelEntry e = scene_json::label_entry(*v.labels, static_cast<int32_t>(at->value));
        entry["label"] = e.name.empty() ? fmt::format("label {}", e.value) : e.name;
      }
    }
    values.push_back(std::move(entry));
  }
  Json out = {{"type", "probe"}, {"point", vec_json(point)}, {"values", std::move(values)}};
  if (message.contains("seq")) out["seq"] = message["seq"];
  return out;
}

}  // namespace imx::server
