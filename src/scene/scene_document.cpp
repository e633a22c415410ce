// SceneDocument: edits of a scene's JSON parsed again whole by the scene loader.
#include "scene/scene_document.hpp"

#include <utility>

#include <fmt/format.h>

#include "scene/overrides.hpp"
#include "scene/world_space.hpp"

namespace imx {

SceneDocument SceneDocument::load(const std::filesystem::path& file,
                                  const std::vector<std::string>& overrides,
                                  const VolumeRegionChooser& region) {
  const std::string text = scene_json::read_scene_file(file);
  SceneDocument d;
  d.origin_ = file.string();
  d.file_ = file;
  d.context_.base_dir = file.parent_path().empty() ? "." : file.parent_path();
  d.context_.region = region;
  nlohmann::json json = scene_json::parse_scene_json(text, d.origin_);
  for (const std::string& assignment : overrides)
    scene_json::apply_override(json, assignment, d.origin_);
  d.parse(std::move(json));
  return d;
}

SceneDocument SceneDocument::from_text(const std::string& text, const std::string& origin,
                                       const std::filesystem::path& base_dir,
                                       const std::vector<std::string>& overrides) {
  nlohmann::json json = scene_json::parse_scene_json(text, origin);
  for (const std::string& assignment : overrides)
    scene_json::apply_override(json, assignment, origin);
  return SceneDocument(std::move(json), origin, base_dir);
}

SceneDocument::SceneDocument(nlohmann::json json, std::string origin,
                             std::filesystem::path base_dir, GivenData given,
                             std::filesystem::path file, VolumeRegionChooser region)
    : origin_(std::move(origin)), file_(std::move(file)) {
  context_.base_dir = std::move(base_dir);
  context_.region = std::move(region);
  context_.given_volumes = std::move(given.volumes);
  context_.given_meshes = std::move(given.meshes);
  context_.given_streamlines = std::move(given.streamlines);
  parse(std::move(json));
}

void SceneDocument::parse(nlohmann::json json) {
  // The loader resets these per parse: a failed parse must leave the current document's own.
  auto used = context_.used;
  auto looks = context_.automatic_looks;
  Scene scene;
  try {
    scene = scene_json::parse_scene_document(json, origin_, context_);
  } catch (...) {
    context_.used = std::move(used);
    context_.automatic_looks = std::move(looks);
    context_.notes.clear();
    throw;
  }
  scene.file = file_;
  annotations_ = std::move(context_.annotations);
  context_.annotations.clear();
  // Sources the document no longer uses are let go.
  auto prune = [&](auto& cache) {
    for (auto it = cache.begin(); it != cache.end();)
      it = context_.used.count(it->first) ? std::next(it) : cache.erase(it);
  };
  prune(context_.volumes);
  prune(context_.meshes);
  prune(context_.placed_meshes);
  prune(context_.streamlines);
  prune(context_.placed_streamlines);
  json_ = std::move(json);
  scene_ = std::move(scene);
}

std::string SceneDocument::text() const {
  return json_.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

void SceneDocument::set(const std::string& assignment, const std::string& edit_name) {
  edit([&](nlohmann::json& json) {
    scene_json::apply_override(json, assignment, origin_, edit_name);
  });
}

void SceneDocument::edit(const std::function<void(nlohmann::json&)>& change) {
  nlohmann::json json = json_;
  change(json);
  parse(std::move(json));
}

void SceneDocument::edit(const std::function<void(nlohmann::json&)>& change, GivenData given) {
  nlohmann::json json = json_;
  change(json);
  std::swap(context_.given_volumes, given.volumes);
  std::swap(context_.given_meshes, given.meshes);
  std::swap(context_.given_streamlines, given.streamlines);
  try {
    parse(std::move(json));
  } catch (...) {
    std::swap(context_.given_volumes, given.volumes);
    std::swap(context_.given_meshes, given.meshes);
    std::swap(context_.given_streamlines, given.streamlines);
    throw;
  }
}

void SceneDocument::write_out_choices() {
  nlohmann::json json = json_;
  nlohmann::json& camera = json["camera"];
  if (!camera.is_object() || camera.contains("view")) {
    const Camera& c = scene_.camera;
    if (!camera.is_object()) camera = nlohmann::json::object();
    camera.erase("view");
    // In the document's own space ("space": "RAS" flips x and y; to_lps undoes itself).
    auto written = [&](const glm::dvec3& v) {
      const glm::dvec3 w = scene_json::to_lps(v, context_.world_space);
      return nlohmann::json{w.x, w.y, w.z};
    };
    camera["eye"] = written(c.eye);
    camera["target"] = written(c.target);
    camera["up"] = written(c.up);
    camera["fov_deg"] = c.fov_deg;
    if (c.projection == Projection::orthographic) camera["ortho_height"] = c.ortho_height;
  }
  if (json.contains("objects") && json["objects"].is_array()) {
    nlohmann::json& objects = json["objects"];
    for (size_t i = 0; i < objects.size(); ++i) {
      auto it = context_.automatic_looks.find(fmt::format("objects[{}]", i));
      if (it == context_.automatic_looks.end()) continue;
      objects[i]["transfer_function"] = it->second.first;
      if (!it->second.second.is_null() && !objects[i].contains("shading"))
        objects[i]["shading"] = it->second.second;
    }
  }
  // What the notes said of the choices ("no camera: ...") still holds for the written document.
  std::vector<std::string> notes = scene_.notes;
  parse(std::move(json));
  scene_.notes = std::move(notes);
}

}  // namespace imx
