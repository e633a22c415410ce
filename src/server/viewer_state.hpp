// ViewerState: the scene a viewer session shows, as imx::Scene (what renders) and as the scene
// file's JSON with every edit applied (what "save scene" writes), changed together by one edit
// message at a time so that the saved file renders the same bytes as the session.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "intermix/scene.hpp"
#include "scene/scene_document.hpp"
#include "volume/display_window.hpp"

namespace imx::server {

struct ViewerState {
  // The scene file (after --set overrides) with every edit applied, and the Scene parsed from it:
  // what "save scene" writes and what renders, changed together.
  SceneDocument document;
  std::filesystem::path file;  // the scene file, or where saves of a scene from files go
  Camera initial_camera;       // "reset view"
  // Per object in scene order: the user's opacity (0..1). For a mesh or a plane it is the
  // material's opacity; for a volume it scales the alphas of its transfer function.
  std::vector<float> opacity;
  std::vector<bool> visible;  // per object in scene order
  // Per volume (scene.volumes order): the user's transfer function, before opacity and
  // visibility scale its alphas into scene.volumes[i].transfer_function.
  std::vector<TransferFunction> transfer_functions;
  // Per volume: the label values its voxels hold (label volumes only; empty for the others), and
  // the voxels they were counted in (a frame edit loads other ones).
  std::vector<std::vector<int32_t>> label_values;
  std::vector<std::shared_ptr<const VolumeData>> label_data;
  // Per volume: the 2-D views' window when the scene gives none, by the initial-window rule on
  // the voxels loaded first (a 4-D series keeps it through its frames, so cine does not flicker).
  std::vector<InitialWindow> initial_windows;

  const Scene& scene() const { return document.scene(); }
};

// The session state of a scene document: the camera framing chose and each automatic transfer
// function are written into the document (so that edits keep them); `file` is where saves go
// beside (its stem names them). Throws imx::Error as the loader does.
ViewerState viewer_state(SceneDocument document, std::filesystem::path file);

// viewer_state of the scene file with --set overrides, saved beside it.
ViewerState load_viewer_state(const std::filesystem::path& file,
                              const std::vector<std::string>& overrides = {});

// Applies one client message of type "camera" or "edit" (docs/viewer.md, protocol); any other
// type is an error (the server handles "settings" itself). Objects are named, never indexed, and
// never by file path. The edited document is parsed again whole (SceneDocument::edit). Throws
// imx::Error naming the field and value at fault, and then leaves the state unchanged. Returns
// true when the image may change (false for an edit that changes nothing, or only a volume's
// window, which its 2-D views show). Data (VolumeData, Mesh) keeps its identity across edits, so
// the Renderer's caches recognise it.
bool apply_edit(ViewerState& state, const nlohmann::json& message);

// The window the 2-D views show volume `i` (scene.volumes order) through: the scene's "window"
// for it (the user's), else the initial-window rule's.
glm::dvec2 volume_window(const ViewerState& state, size_t i);

// The session's camera, initial_camera and objects as sent to clients ("hello" and "state").
nlohmann::json describe_state(const ViewerState& state);

// Per volume, by name: {"range": [lo, hi], "counts": [...]} over `bins` (1..4096) bins of its
// values; large volumes are subsampled on a regular grid of about 4M voxels.
nlohmann::json describe_histograms(const Scene& scene, int bins = 128);

// 3D Slicer's volume-rendering presets as transfer-function points, by the name a scene file
// gives them: {"ct-bone": [[value, r, g, b, a], ...], ...}, for the page's preset menu.
nlohmann::json describe_tf_presets();

}  // namespace imx::server
