// SceneDocument: a scene as its JSON document and as the imx::Scene parsed from it, changed
// together. Every editor of a scene (the CLI's --set, the viewer's edit messages, the Python
// Scene) changes the document and lets the one scene loader parse it, so that what is saved is
// always what renders.
#pragma once
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "intermix/scene.hpp"
#include "scene/scene_parsers.hpp"

namespace imx {

// Volumes and meshes a program gives instead of files (the Python package's numpy arrays), by
// the ID a {"$volume": ID} or {"$mesh": ID} source names.
struct GivenData {
  std::map<std::string, std::shared_ptr<const VolumeData>> volumes;
  std::map<std::string, std::shared_ptr<const Mesh>> meshes;
  std::map<std::string, std::shared_ptr<const Streamlines>> streamlines;  // {"$streamlines": ID}
};

class SceneDocument {
 public:
  // A scene file with --set assignments applied in order, read as load_scene reads it; with
  // `region`, each volume object's data is only the box it chooses.
  static SceneDocument load(const std::filesystem::path& file,
                            const std::vector<std::string>& overrides = {},
                            const VolumeRegionChooser& region = {});
  // A scene file's text; `origin` names it in errors, relative paths start at `base_dir`.
  static SceneDocument from_text(const std::string& text, const std::string& origin,
                                 const std::filesystem::path& base_dir,
                                 const std::vector<std::string>& overrides = {});
  // A document already in JSON form; with `region`, as load's. Throws imx::Error as the loader
  // does.
  SceneDocument(nlohmann::json json, std::string origin, std::filesystem::path base_dir,
                GivenData given = {}, std::filesystem::path file = {},
                VolumeRegionChooser region = {});

  const nlohmann::json& json() const { return json_; }
  const Scene& scene() const { return scene_; }
  // The document's "annotations", parsed (points in LPS): measurements kept with the scene,
  // which rendering leaves out (src/measure/ measures them, src/annotate/ draws them).
  const std::vector<Annotation>& annotations() const { return annotations_; }
  Scene take_scene() && { return std::move(scene_); }
  const std::string& origin() const { return origin_; }
  const std::filesystem::path& base_dir() const { return context_.base_dir; }
  // The document as a scene file's text (invalid UTF-8 in strings replaced).
  std::string text() const;

  // One --set assignment "path=value" (scene_json::apply_override); `edit` names it in errors
  // instead ("scene.set('path')").
  void set(const std::string& assignment, const std::string& edit = "");
  // `change` edits a copy of the document, which is parsed whole; only when that succeeds do the
  // document and the scene change (on any error both stay as they were). Sources are read once
  // per document and keep their identity across edits (imx::Renderer knows data by it); those
  // the new document no longer uses are let go. With `given`, it replaces the given data.
  void edit(const std::function<void(nlohmann::json&)>& change);
  void edit(const std::function<void(nlohmann::json&)>& change, GivenData given);
  // Writes what reading chose into the document: the camera framing placed (for a document
  // without one, or with a "view"), and each volume's automatic transfer function and shading.
  // Later edits then keep them, and a saved document renders the same image.
  void write_out_choices();

 private:
  SceneDocument() = default;
  void parse(nlohmann::json json);

  nlohmann::json json_;
  std::string origin_;
  std::filesystem::path file_;
  scene_json::SceneContext context_;
  Scene scene_;
  std::vector<Annotation> annotations_;
};

}  // namespace imx
