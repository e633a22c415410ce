// The viewer's client messages (docs/viewer.md, protocol): the input is one message's text,
// parsed by the strict scene parser and applied with apply_edit (apply_annotations for the
// measurements' `annotations`) to a copy of one small session (a volume, a CSG pair of meshes and
// a plane, made once). A refused message must leave the session as it was; an accepted one must
// save a scene file that loads as the session's scene.
// Then the same text goes to a live ViewerSession (every message type, its render thread
// running), which must answer it without throwing.
#include <chrono>
#include <cstdlib>
#include <exception>
#include <string>

#include <nlohmann/json.hpp>

#include "harness.hpp"
#include "intermix/error.hpp"
#include "intermix/scene.hpp"
#include "scene/scene_document.hpp"
#include "scene/strict_json.hpp"
#include "server/annotation_messages.hpp"
#include "server/viewer_session.hpp"
#include "server/viewer_state.hpp"

namespace {

// The viewer's bound on one message (docs/viewer.md).
constexpr size_t kMaxMessage = 64 * 1024;

constexpr const char* kScene = R"({
  "camera": {"eye": [0, -300, 0], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 30},
  "image": {"width": 8, "height": 8},
  "objects": [
    {"name": "ct", "type": "volume", "source": {"phantom": "ct-head", "size": 12},
     "transfer_function": {"preset": "ct-bone"},
     "clip_planes": [{"point": [0, 0, 0], "normal": [0, 0, 1]}]},
    {"name": "ball", "type": "mesh", "source": {"primitive": "sphere", "radius": 20, "segments": 8},
     "material": {"opacity": 0.5}, "interior": {"opacity": 0.2}},
    {"name": "cube", "type": "mesh", "source": {"primitive": "box", "size": 10}, "visible": false},
    {"name": "axial", "type": "plane", "volume": "ct", "normal": [0, 0, 1], "window": [40, 400]}
  ],
  "csg": {"op": "difference", "a": "ball", "b": "cube"}})";

const imx::server::ViewerState& session() {
  static const imx::server::ViewerState state = [] {
    const std::filesystem::path file = imx::fuzz::scratch().write("session.json", kScene);
    return imx::server::load_viewer_state(file);
  }();
  return state;
}

// Takes whatever the live session sends.
struct NullSink : imx::server::ClientSink {
  void send_text(std::string) override {}
  void send_frame(std::string, std::string, bool) override {}
};

imx::server::ViewerSession& live_session() {
  static imx::server::ViewerSession live = [] {
    imx::server::SessionOptions options;
    options.log = false;
    options.release_after_ms = 1;  // a "moving" input is released at once: frames stay quick
    // A "viewport" setting resizes every frame up to this bound; the default (2048) lets one
    // input ask for frames that take longer than the 5 s wait below under ASan.
    options.max_image_side = 64;
    return imx::server::ViewerSession(session(), options);
  }();
  return live;
}

bool same_tf(const imx::TransferFunction& a, const imx::TransferFunction& b) {
  if (a.unit_distance != b.unit_distance || a.points.size() != b.points.size()) return false;
  for (size_t i = 0; i < a.points.size(); ++i)
    if (a.points[i].value != b.points[i].value || a.points[i].rgba != b.points[i].rgba)
      return false;
  return true;
}

// What renders, compared field by field between the session and its saved file.
bool same_scene(const imx::Scene& a, const imx::Scene& b) {
  if (a.camera.eye != b.camera.eye || a.camera.target != b.camera.target ||
      a.camera.up != b.camera.up || a.camera.fov_deg != b.camera.fov_deg)
    return false;
  if (a.volumes.size() != b.volumes.size() || a.meshes.size() != b.meshes.size() ||
      a.planes.size() != b.planes.size())
    return false;
  for (size_t i = 0; i < a.volumes.size(); ++i) {
    const imx::VolumeObject &x = a.volumes[i], &y = b.volumes[i];
    if (!same_tf(x.transfer_function, y.transfer_function) ||
        x.clip_planes.size() != y.clip_planes.size() || x.shading.enabled != y.shading.enabled ||
        x.shading.ambient != y.shading.ambient || x.shading.diffuse != y.shading.diffuse ||
        x.shading.specular != y.shading.specular || x.shading.shininess != y.shading.shininess ||
        x.window != y.window)
      return false;
    for (size_t c = 0; c < x.clip_planes.size(); ++c)
      if (x.clip_planes[c].point != y.clip_planes[c].point ||
          x.clip_planes[c].normal != y.clip_planes[c].normal)
        return false;
  }
  for (size_t i = 0; i < a.meshes.size(); ++i) {
    const imx::MeshObject &x = a.meshes[i], &y = b.meshes[i];
    if (x.material.opacity != y.material.opacity ||
        x.interior.has_value() != y.interior.has_value() ||
        (x.interior && x.interior->opacity != y.interior->opacity))
      return false;
  }
  for (size_t i = 0; i < a.planes.size(); ++i) {
    const imx::PlaneObject &x = a.planes[i], &y = b.planes[i];
    if (x.center != y.center || x.normal != y.normal || x.up != y.up || x.size != y.size ||
        x.window != y.window || x.opacity != y.opacity || x.volume != y.volume)
      return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  if (size > kMaxMessage) return 0;  // the server refuses longer messages before parsing
  const imx::server::ViewerState& original = session();
  static const auto sink = [] {
    auto s = std::make_shared<NullSink>();
    live_session().add_client(s);
    return s;
  }();
  live_session().on_message(sink, std::string(as_view(data, size)));
  // Each input's frames finish before the next input (reproducible), and before the process
  // exits: a frame rendering during exit read caches already destroyed (ASan, fork mode).
  if (!live_session().wait_idle(std::chrono::seconds(5))) __builtin_trap();
  imx::server::ViewerState state = original;
  nlohmann::json message;
  try {
    message = imx::scene_json::parse_strict_json(std::string(as_view(data, size)), "message");
  } catch (const std::exception& e) {
    refused(e);
    return 0;
  }
  // The measurements' edit (issue 47) goes through the document as an object edit does.
  const bool annotations =
      message.is_object() && message.contains("type") && message["type"] == "annotations";
  try {
    if (annotations)
      imx::server::apply_annotations(state, message);
    else
      imx::server::apply_edit(state, message);
    accepted(annotations ? "annotations" : "edit");
  } catch (const imx::Error& e) {
    refused(e);
    // Strong guarantee: a refused edit changed nothing.
    if (state.document.json() != original.document.json() || state.visible != original.visible ||
        state.opacity != original.opacity || !same_scene(state.scene(), original.scene()))
      __builtin_trap();
    return 0;
  }
  (void)imx::server::describe_state(state);
  // The saved file loads as what the session renders.
  const std::string text = state.document.text();
  imx::Scene reloaded;
  try {
    reloaded = imx::parse_scene(text, scratch().path(), "saved");
  } catch (const imx::Error& e) {
    std::fprintf(stderr, "the saved scene does not load: %s\n%s\n", e.what(), text.c_str());
    __builtin_trap();
  }
  if (imx::SceneDocument::from_text(text, "saved", scratch().path()).annotations().size() !=
      state.document.annotations().size()) {
    std::fprintf(stderr, "the saved scene's annotations differ:\n%s\n", text.c_str());
    __builtin_trap();
  }
  if (!same_scene(state.scene(), reloaded)) {
    std::fprintf(stderr, "the saved scene differs from the session:\n%s\n", text.c_str());
    __builtin_trap();
  }
  return 0;
}
