// intermix.Scene: a scene's JSON document beside the parsed imx::Scene, changed together.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "document.hpp"
#include "intermix/scene.hpp"
#include "scene/scene_document.hpp"

namespace imx::server {
class ViewerSession;
}

namespace imx::python {

// The notebook views (Scene.show) a Scene is shown in, each with the document count it last
// agreed on. A copy of a Scene (a render with another view) is not shown: its links start empty.
class ViewLinks {
 public:
  ViewLinks() = default;
  ViewLinks(const ViewLinks&) {}
  ViewLinks& operator=(const ViewLinks&) { return *this; }

  struct Link {
    std::weak_ptr<server::ViewerSession> session;
    uint64_t seen = 0;
  };
  std::vector<Link> links;
};

// Every change (set, add_*) is a SceneDocument edit: the whole document is parsed again by the
// scene loader, with its own errors, and replaces the current one only when it parses. Sources
// are read once and keep their identity (imx::Renderer reuses what it rendered of unchanged
// objects). The Python objects given as sources are kept beside it, for to_dict.
class PyScene {
 public:
  // `origin` names the document in errors (the file, or "scene dict"); relative paths resolve
  // against `base_dir`.
  PyScene(nlohmann::json document, GivenSources sources, std::string origin,
          std::filesystem::path base_dir, std::filesystem::path file = {});
  // A document already parsed (a scene built from files), with no Python sources.
  explicit PyScene(SceneDocument document);

  // Both first take in what a page showing this scene changed (pull).
  const Scene& scene() const {
    pull();
    return document_.scene();
  }
  const nlohmann::json& document() const {
    pull();
    return document_.json();
  }
  const GivenSources& sources() const { return sources_; }
  const SceneDocument& scene_document() const {
    pull();
    return document_;
  }
  // Shows this scene's edits in `session`'s pages, and their edits here (Scene.show).
  void attach(const std::shared_ptr<server::ViewerSession>& session, uint64_t seen);
  const std::string& origin() const { return origin_; }
  const std::filesystem::path& file() const { return file_; }
  const std::filesystem::path& base_dir() const { return document_.base_dir(); }
  const std::vector<std::string>& notes() const { return notes_; }

  // `path` as --set takes it; `value` any scene value (document.hpp).
  void set(const std::string& path, const py::handle& value);
  // Several assignments applied in order and checked once, as one edit.
  void set(const std::vector<std::pair<std::string, py::object>>& assignments);
  // The camera framing the objects from a patient direction ("left": scene files' camera
  // "view"), keeping its fov_deg and projection.
  void look_from(const std::string& view);
  // Appends an object {"name", "type", "source"?, **fields} to the document's objects.
  void add(const std::string& name, const std::string& type, const py::object& source,
           const py::dict& fields);

 private:
  void rebuild(nlohmann::json document, GivenSources sources);
  void keep_notes();
  // The document a page changed last, if one did since this scene last agreed with it; the
  // other pages then show it too. With the GIL held, as every change of a scene.
  void pull() const;
  // This scene's document to every page showing it.
  void push();

  GivenSources sources_;
  std::string origin_;
  std::filesystem::path file_;
  mutable SceneDocument document_;
  std::vector<std::string> notes_;
  mutable ViewLinks views_;
};

}  // namespace imx::python
