// intermix.Scene: a scene's JSON document beside the parsed imx::Scene, changed together.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "document.hpp"
#include "intermix/scene.hpp"
#include "scene/scene_parsers.hpp"

namespace imx::python {

// Every change (set, add_*) edits a copy of the document and parses it again through the scene
// loader, with the loader's own errors; only a document that parses replaces the current one.
// The loader context is kept between parses, so sources are read once and keep their identity
// (imx::Renderer reuses what it rendered of unchanged objects).
class PyScene {
 public:
  // `origin` names the document in errors (the file, or "scene dict"); relative paths resolve
  // against `base_dir`.
  PyScene(nlohmann::json document, GivenSources sources, std::string origin,
          std::filesystem::path base_dir, std::filesystem::path file = {});

  const Scene& scene() const { return scene_; }
  const nlohmann::json& document() const { return document_; }
  const GivenSources& sources() const { return sources_; }
  const std::string& origin() const { return origin_; }
  const std::filesystem::path& file() const { return file_; }
  const std::filesystem::path& base_dir() const { return context_.base_dir; }
  const std::vector<std::string>& notes() const { return notes_; }

  // `path` as --set takes it; `value` any scene value (document.hpp).
  void set(const std::string& path, const py::handle& value);
  // Appends an object {"name", "type", "source"?, **fields} to the document's objects.
  void add(const std::string& name, const std::string& type, const py::object& source,
           const py::dict& fields);

 private:
  void rebuild(nlohmann::json document, GivenSources sources);

  nlohmann::json document_;
  GivenSources sources_;
  std::string origin_;
  std::filesystem::path file_;
  detail::SceneContext context_;
  Scene scene_;
  std::vector<std::string> notes_;
};

}  // namespace imx::python
