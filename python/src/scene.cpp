// intermix.Scene: from a file, a dict or nothing; --set edits; objects added from numpy.
#include "scene.hpp"

#include <algorithm>
#include <set>
#include <system_error>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/stl.h>

#include "arguments.hpp"
#include "intermix/error.hpp"
#include "measure/measurement.hpp"
#include "render.hpp"
#include "scene/camera_framing.hpp"
#include "scene/overrides.hpp"
#include "scene/scene_from_files.hpp"
#include "server/viewer_session.hpp"

namespace imx::python {
namespace {

constexpr const char* kDictOrigin = "scene dict";

bool is_mapping(const py::handle& value) {
  return py::isinstance<py::dict>(value) ||
         py::isinstance(value, py::module_::import("collections.abc").attr("Mapping"));
}

// The folder relative paths resolve against: `base_dir`, else the current one.
std::filesystem::path folder_of(const py::handle& base_dir, std::string_view function) {
  if (auto folder = optional_path(base_dir, {function, "base_dir"})) return *folder;
  std::error_code ec;
  std::filesystem::path cwd = std::filesystem::current_path(ec);
  return ec ? std::filesystem::path(".") : cwd;
}

std::shared_ptr<PyScene> from_file(const PathParameter& path) {
  const std::filesystem::path file = python::path(path, {"Scene.from_file", "path"});
  const std::string text = scene_json::read_scene_file(file);
  std::filesystem::path base_dir = file.parent_path();
  if (base_dir.empty()) base_dir = ".";
  return std::make_shared<PyScene>(scene_json::parse_scene_json(text, file.string()),
                                   GivenSources{}, file.string(), base_dir, file);
}

std::shared_ptr<PyScene> from_files(const py::handle& paths, const TextParameter& view_argument) {
  const Argument argument{"Scene.from_files", "paths"};
  std::vector<std::filesystem::path> files;
  if (is_path_like(paths)) {
    files.push_back(python::path(paths, argument));
  } else if (py::isinstance<py::sequence>(paths) && !py::isinstance<py::str>(paths)) {
    for (const py::handle& p : py::reinterpret_borrow<py::sequence>(paths))
      files.push_back(python::path(p, argument));
  } else {
    throw_wrong_type(argument, "a path or a list of paths", paths);
  }
  const std::string view = text(view_argument, {"Scene.from_files", "view"});
  if (!find_patient_view(view))
    throw py::value_error(fmt::format("Scene.from_files: view '{}' is not one of {}", view,
                                      fmt::join(patient_view_names(), ", ")));
  return std::make_shared<PyScene>(scene_from_files(files, view));
}

std::shared_ptr<PyScene> from_dict(const SceneDictParameter& dict,
                                   const OptionalPathParameter& base_dir) {
  if (!is_mapping(dict)) throw_wrong_type({"Scene.from_dict", "scene"}, "a dict", dict);
  const std::filesystem::path folder = folder_of(base_dir, "Scene.from_dict");
  GivenSources sources;
  nlohmann::json document = to_document(dict, sources, kDictOrigin);
  return std::make_shared<PyScene>(std::move(document), std::move(sources), kDictOrigin, folder);
}

// A file source's dict: {"file": path}.
py::dict file_source(const py::handle& source, const Argument& argument) {
  return py::dict(py::arg("file") = py::str(python::path(source, argument).string()));
}

// A volume source from Python: a Volume, an array (with `affine` and `space`), a source dict or
// a file path.
py::object volume_source(const py::handle& source, const py::handle& affine,
                         const py::handle& space, const py::handle& axes, const py::handle& frame) {
  const Argument argument{"Scene.add_volume", "source"};
  py::module_ images = py::module_::import("intermix._images");
  if (py::isinstance<py::array>(source) || images.attr("is_image")(source).cast<bool>() ||
      images.attr("is_array_proxy")(source).cast<bool>())
    return py::type::of<PyVolume>()(source, affine, py::arg("space") = space,
                                    py::arg("axes") = axes, py::arg("frame") = frame);
  optional_text(space, {"Scene.add_volume", "space"});
  if (!affine.is_none())
    throw py::value_error("Scene.add_volume: affine goes with an array source only");
  if (text(axes, {"Scene.add_volume", "axes"}) != "auto" || !frame.is_none())
    throw py::value_error(
        "Scene.add_volume: axes and frame go with an array or image source only (a file's "
        "frame is its source dict's \"frame\")");
  if (is_path_like(source) || PyBytes_Check(source.ptr())) return file_source(source, argument);
  if (py::isinstance<PyVolume>(source) || is_mapping(source))
    return py::reinterpret_borrow<py::object>(source);
  throw_wrong_type(argument, "an intermix.Volume, a numpy array, a path or a source dict", source);
}

py::object mesh_source(const py::handle& source) {
  const Argument argument{"Scene.add_mesh", "source"};
  if (is_path_like(source) || PyBytes_Check(source.ptr())) return file_source(source, argument);
  if (py::isinstance<PyMesh>(source) || is_mapping(source))
    return py::reinterpret_borrow<py::object>(source);
  throw_wrong_type(argument, "an intermix.Mesh, a path or a source dict", source);
}

// A streamlines source: an intermix.Streamlines, a path or a source dict as they are, anything
// else (a nibabel Tractogram, an ArraySequence, a list of arrays) made a Streamlines.
py::object streamlines_source(const py::handle& source) {
  if (is_path_like(source) || PyBytes_Check(source.ptr()))
    return file_source(source, {"Scene.add_streamlines", "source"});
  if (py::isinstance<PyStreamlines>(source) || is_mapping(source))
    return py::reinterpret_borrow<py::object>(source);
  return py::type::of<PyStreamlines>()(source);
}

// The name an added object gets: `given`, else `stem` made unique among the scene's names.
std::string object_name_for(const PyScene& s, const std::optional<std::string>& given,
                            const std::string& stem) {
  if (given) return *given;
  auto taken = [&](const std::string& n) {
    for (const ObjectRef& ref : s.scene().order)
      if (object_name(s.scene(), ref) == n) return true;
    return false;
  };
  const std::string base = stem.empty() ? "streamlines" : stem;
  std::string name = base;
  for (int n = 2; taken(name); ++n) name = fmt::format("{}-{}", base, n);
  return name;
}

// A tractogram file's name without its extensions: "cst" for cst.trk.gz.
std::string file_stem(const py::handle& source) {
  if (!is_path_like(source)) return "streamlines";
  std::filesystem::path file = python::path(source, {"Scene.add_streamlines", "source"});
  if (file.extension() == ".gz") file = file.stem();
  // Scene names hold no '.', '[', ']' or '=' (they separate --set paths).
  std::string stem = file.stem().string();
  std::replace_if(
      stem.begin(), stem.end(), [](char c) { return c == '.' || c == '[' || c == ']' || c == '='; },
      '_');
  return stem;
}

const std::vector<std::string> kColourings = {"direction",   "streamline_direction", "fixed",
                                              "point_value", "streamline_value",     "group"};

// Scene.add_streamlines: the object's keys from the arguments, then, for a `value` without a
// colouring, whether it names per-point or per-streamline values (the tractogram read).
void add_streamlines(PyScene& s, const py::handle& source, const py::handle& radius,
                     const py::handle& colouring_argument, const py::handle& color,
                     const py::handle& value_argument, const py::handle& colormap,
                     const py::handle& opacity, const py::handle& stride,
                     const py::handle& min_length, const py::handle& name_argument,
                     const py::kwargs& extra) {
  constexpr const char* kFunction = "Scene.add_streamlines";
  const std::optional<std::string> colouring =
      optional_text(colouring_argument, {kFunction, "colouring"});
  if (colouring &&
      std::find(kColourings.begin(), kColourings.end(), *colouring) == kColourings.end())
    throw py::value_error(fmt::format("{}: colouring '{}' is not one of {}", kFunction, *colouring,
                                      fmt::join(kColourings, ", ")));
  const std::optional<std::string> value = optional_text(value_argument, {kFunction, "value"});
  const std::string name =
      object_name_for(s, optional_text(name_argument, {kFunction, "name"}), file_stem(source));
  py::dict fields;
  fields["radius"] = radius;
  if (colouring) fields["color_by"] = py::str(*colouring);
  if (!color.is_none()) fields["color"] = color;
  if (value) fields["value"] = py::str(*value);
  if (!colormap.is_none()) fields["colormap"] = colormap;
  fields["opacity"] = opacity;
  fields["stride"] = stride;
  fields["min_length"] = min_length;
  for (const auto& [key, field] : extra) {
    if (fields.contains(key))
      throw py::type_error(
          fmt::format("{}: {} given twice", kFunction, py::str(key).cast<std::string>()));
    fields[key] = field;
  }
  const PyScene before = s;
  s.add(name, "streamlines", streamlines_source(source), fields);
  if (!value || colouring || fields.contains("color_by")) return;
  const Streamlines& added = *s.scene().streamlines.back().streamlines;
  auto has = [&](const std::vector<StreamlineValues>& list) {
    return std::any_of(list.begin(), list.end(),
                       [&](const StreamlineValues& v) { return v.name == *value; });
  };
  const char* by = has(added.point_values)        ? "point_value"
                   : has(added.streamline_values) ? "streamline_value"
                                                  : nullptr;
  if (!by) {
    std::vector<std::string> names;
    for (const auto* list : {&added.point_values, &added.streamline_values})
      for (const StreamlineValues& v : *list) names.push_back("'" + v.name + "'");
    s = before;
    throw py::value_error(
        fmt::format("{}: the streamlines have no values named '{}' ({})", kFunction, *value,
                    names.empty() ? std::string("they have none")
                                  : "they have " + fmt::format("{}", fmt::join(names, ", "))));
  }
  try {
    s.set(fmt::format("objects.{}.color_by", s.document()["objects"].size() - 1), py::str(by));
  } catch (...) {
    s = before;
    throw;
  }
}

}  // namespace

namespace {

// The data of the Volume and Mesh objects among `sources`, for the loader.
GivenData given_data(const GivenSources& sources) {
  GivenData given;
  for (const auto& [id, object] : sources) {
    if (py::isinstance<PyVolume>(object))
      given.volumes[id] = object.cast<const PyVolume&>().data;
    else if (py::isinstance<PyStreamlines>(object))
      given.streamlines[id] = object.cast<const PyStreamlines&>().data;
    else
      given.meshes[id] = object.cast<const PyMesh&>().mesh;
  }
  return given;
}

// `document` (copied with the GIL held) shown by `session`; returns the session's new count.
uint64_t replace_without_gil(server::ViewerSession& session, const SceneDocument& document) {
  SceneDocument copy = document;
  py::gil_scoped_release release;
  return session.replace_document(std::move(copy));
}

}  // namespace

PyScene::PyScene(nlohmann::json document, GivenSources sources, std::string origin,
                 std::filesystem::path base_dir, std::filesystem::path file)
    : origin_(std::move(origin)),
      file_(std::move(file)),
      document_(document, origin_, std::move(base_dir), given_data(sources), file_) {
  keep_named_sources(document, sources);
  sources_ = std::move(sources);
  keep_notes();
}

PyScene::PyScene(SceneDocument document)
    : origin_(document.origin()), document_(std::move(document)) {
  keep_notes();
}

// With the GIL held: another thread may not change this scene meanwhile.
void PyScene::rebuild(nlohmann::json document, GivenSources sources) {
  document_.edit([&](nlohmann::json& json) { json = document; }, given_data(sources));
  keep_named_sources(document, sources);
  sources_ = std::move(sources);
  keep_notes();
  push();
}

void PyScene::attach(const std::shared_ptr<server::ViewerSession>& session, uint64_t seen) {
  views_.links.push_back({session, seen});
}

// The session's calls take its lock, which its render thread may hold while letting go of a
// numpy array (which takes the GIL): they are made without the GIL.
void PyScene::pull() const {
  std::erase_if(views_.links, [](const ViewLinks::Link& l) { return l.session.expired(); });
  for (ViewLinks::Link& link : views_.links) {
    const std::shared_ptr<server::ViewerSession> session = link.session.lock();
    std::pair<SceneDocument, uint64_t> shown = [&] {
      py::gil_scoped_release release;
      return session->document();
    }();
    if (shown.second == link.seen) continue;
    document_ = std::move(shown.first);
    link.seen = shown.second;
    for (ViewLinks::Link& other : views_.links)
      if (&other != &link)
        if (const auto s = other.session.lock()) other.seen = replace_without_gil(*s, document_);
  }
}

void PyScene::push() {
  std::erase_if(views_.links, [](const ViewLinks::Link& l) { return l.session.expired(); });
  for (ViewLinks::Link& link : views_.links)
    if (const auto session = link.session.lock())
      link.seen = replace_without_gil(*session, document_);
}

void PyScene::keep_notes() {
  for (const std::string& note : document_.scene().notes)
    if (std::find(notes_.begin(), notes_.end(), note) == notes_.end()) notes_.push_back(note);
}

void PyScene::set(const std::string& path, const py::handle& value) {
  set({{path, py::reinterpret_borrow<py::object>(value)}});
}

void PyScene::set(const std::vector<std::pair<std::string, py::object>>& assignments) {
  pull();
  GivenSources sources = sources_;
  nlohmann::json document = document_.json();
  for (const auto& [path, value] : assignments) {
    if (path.find('=') != std::string::npos)
      throw py::value_error(
          fmt::format("{}: scene.set('{}'): a key path has no '='", origin_, path));
    const nlohmann::json json_value = to_document(value, sources, origin_, path);
    scene_json::apply_override(document, path + "=" + json_value.dump(), origin_,
                               fmt::format("scene.set('{}')", path));
  }
  rebuild(std::move(document), std::move(sources));
}

void PyScene::look_from(const std::string& view) {
  if (!find_patient_view(view))
    throw py::value_error(fmt::format("{}: view '{}' is not one of {}", origin_, view,
                                      fmt::join(patient_view_names(), ", ")));
  pull();
  nlohmann::json document = document_.json();
  nlohmann::json camera = nlohmann::json::object();
  const auto old = document.find("camera");
  if (old != document.end() && old->is_object())
    for (const char* kept : {"fov_deg", "projection"})
      if (old->contains(kept)) camera[kept] = (*old)[kept];
  camera["view"] = view;
  document["camera"] = std::move(camera);
  rebuild(std::move(document), sources_);
}

void PyScene::add(const std::string& name, const std::string& type, const py::object& source,
                  const py::dict& fields) {
  pull();
  const nlohmann::json& current = document_.json();
  auto objects = current.find("objects");
  const size_t index =
      objects != current.end() && objects->is_array() ? objects->size() : size_t{0};
  const std::string path = fmt::format("objects[{}]", index);
  GivenSources sources = sources_;
  nlohmann::json object = to_document(fields, sources, origin_, path);
  object["name"] = name;
  object["type"] = type;
  if (!source.is_none()) object["source"] = to_document(source, sources, origin_, path + ".source");
  nlohmann::json document = current;
  nlohmann::json& list = document["objects"];
  if (list.is_null()) list = nlohmann::json::array();
  if (!list.is_array())
    throw py::value_error(
        fmt::format("{}: objects: expected an array, got {}", origin_, list.type_name()));
  list.push_back(std::move(object));
  rebuild(std::move(document), std::move(sources));
}

void bind_scene(py::module_& m) {
  py::class_<PyScene, std::shared_ptr<PyScene>> cls(
      m, "Scene",
      R"doc(A scene: camera, image, lights, volumes, meshes, planes and render settings, in the schema of
intermix's JSON scene files (README "Scene files"). Volumes and meshes come from files, built-in
phantoms and primitives, or numpy (intermix.Volume, intermix.Mesh).

  Scene()                        an empty scene: {"objects": []}
  Scene.from_file(path)          a scene file; relative paths resolve against its folder
  Scene.from_files(paths, view="anterior")
                                 a scene built from volume, DICOM and mesh files alone
  Scene.from_dict(d, base_dir=None)
                                 the same schema as a dict; relative paths resolve against
                                 base_dir (default: the current folder). A volume's or mesh's
                                 "source" may be an intermix.Volume / intermix.Mesh.
  scene.set(path, value)         the CLI's --set: "objects.ct.transfer_function.points", ...
  scene.add_volume / add_mesh / add_plane
  scene.to_dict()                the document (Volume and Mesh objects in place)
  scene.render(...)              an (H, W, 4) float32 intermix.Image, premultiplied linear RGBA

Every change is checked by the scene loader and either applies whole or raises with the
loader's message (ValueError; OSError for files that cannot be read), leaving the scene as it
was. Sources are read once per scene and shared by its changes.
)doc");
  cls.def(py::init([](const OptionalPathParameter& base_dir) {
            return std::make_shared<PyScene>(nlohmann::json{{"objects", nlohmann::json::array()}},
                                             GivenSources{}, kDictOrigin,
                                             folder_of(base_dir, "Scene"));
          }),
          py::arg("base_dir") = py::none(),
          "An empty scene (no objects; default camera, image and lights) to add objects to.")
      .def_static(
          "from_file", &from_file, py::arg("path"),
          R"doc(Loads a JSON scene file, with the same checks and messages as `intermix render`.
Raises OSError when the file (or a file it names) cannot be read, ValueError for what is wrong
in it.
)doc")
      .def_static(
          "from_files",
          [](const py::object& paths, const TextParameter& view) {
            return from_files(paths, view);
          },
          py::arg("paths"), py::arg("view") = "anterior",
          R"doc(A scene built from data files alone, as `intermix render FILE...` builds it: each volume file
(NIfTI, NRRD, MetaImage, MGH, Analyze) or DICOM folder a volume with the transfer function of
what it is (CT preset, PET hot ramp, signed map, mask, else a grey ramp over the robust range),
each mesh file (PLY, STL, OBJ, GIfTI, ...) a mesh in a palette colour, and a camera framing them
all from `view` (anterior, posterior, left, right, superior, inferior). `paths` is one path or a
list. scene.to_dict() is the scene file it built, every choice written out; scene.notes says
what was chosen.
)doc")
      .def_static(
          "from_dict", &from_dict, py::arg("scene"), py::arg("base_dir") = py::none(),
          R"doc(A scene from a dict in the scene-file schema. Values may be numpy arrays and scalars (as lists
and numbers) and paths; a volume object's "source" may be an intermix.Volume and a mesh
object's an intermix.Mesh. Errors name the JSON path as for files ("scene dict: objects[0]...").
)doc")
      .def_static(
          "from_json",
          [](const TextParameter& text_argument, const OptionalPathParameter& base_dir) {
            const std::string json = text(text_argument, {"Scene.from_json", "text"});
            const std::filesystem::path folder = folder_of(base_dir, "Scene.from_json");
            return std::make_shared<PyScene>(scene_json::parse_scene_json(json, "scene text"),
                                             GivenSources{}, "scene text", folder);
          },
          py::arg("text"), py::arg("base_dir") = py::none(),
          "A scene from JSON text (a scene file's content).")
      .def(
          "set",
          [](PyScene& s, const py::object& path, const SceneValueParameter& value) {
            const Argument argument{"Scene.set", "path"};
            if (value.is(py::ellipsis())) {
              if (!is_mapping(path))
                throw py::type_error(
                    "Scene.set: give a path and a value, or one dict of paths and values");
              std::vector<std::pair<std::string, py::object>> assignments;
              for (const py::handle item : path.attr("items")()) {
                const py::tuple kv = py::reinterpret_borrow<py::tuple>(item);
                assignments.emplace_back(text(kv[0], argument), kv[1]);
              }
              s.set(assignments);
              return;
            }
            s.set(text(path, argument), value);
          },
          py::arg("path"), py::arg("value") = py::ellipsis(),
          R"doc(Sets one value by its dotted path, as `intermix render --set path=value` does:
"image.width", "render.spp", "objects.0.material.opacity", or an object by name:
"objects.ct.transfer_function.points". `value` is any scene value (a number, list, dict,
str, numpy array, Volume, Mesh, ...); a dict replaces the whole block
(scene.set("camera", {"eye": ..., "target": ..., "up": ...}): keys it does not give take their
defaults). Missing object keys are created.

scene.set({"camera.eye": [...], "camera.up": [...]}) applies several paths as one edit, checked
once they are all applied (one at a time, the first could leave the camera invalid).

The scene is checked again; on an error it stays as it was.
)doc")
      .def(
          "set_view",
          [](PyScene& s, const TextParameter& view) {
            s.look_from(text(view, {"Scene.set_view", "view"}));
          },
          py::arg("view"),
          R"doc(Points the camera at the objects from a patient direction: "anterior", "posterior", "left",
"right", "superior" or "inferior" (the scene file's camera "view", the CLI's --view), framing
them all; fov_deg and projection are kept. The document's camera is then {"view": ...}, so it
frames again after each edit.
)doc")
      .def(
          "add_volume",
          [](PyScene& s, const TextParameter& name, const VolumeSourceParameter& source,
             const OptionalArrayParameter& affine, const OptionalTextParameter& space,
             const TextParameter& axes, const OptionalIntParameter& frame,
             const py::kwargs& fields) {
            const std::string added_name = text(name, {"Scene.add_volume", "name"});
            s.add(added_name, "volume", volume_source(source, affine, space, axes, frame), fields);
          },
          py::arg("name"), py::arg("source"), py::arg("affine") = py::none(),
          py::arg("space") = py::none(), py::arg("axes") = "auto", py::arg("frame") = py::none(),
          R"doc(Adds a volume object. `source` is an intermix.Volume, a numpy array or a nibabel image (made a
Volume with `affine`, `space`, `axes` and `frame`, as intermix.Volume takes them), a file path,
or a source dict ({"phantom": "ct-head", "size": 128}). Keyword
arguments are the object's other keys: transfer_function={"preset": "ct-bone"} or
{"points": [[value, r, g, b, a], ...]}, style, shading, transform, clip_planes, clip, visible.
)doc")
      .def(
          "add_mesh",
          [](PyScene& s, const TextParameter& name, const MeshSourceParameter& source,
             const py::kwargs& fields) {
            const std::string added_name = text(name, {"Scene.add_mesh", "name"});
            s.add(added_name, "mesh", mesh_source(source), fields);
          },
          py::arg("name"), py::arg("source"),
          R"doc(Adds a mesh object. `source` is an intermix.Mesh, a file path or a source dict
({"primitive": "sphere", "radius": 20}). Keyword arguments are the object's other keys:
material={"color": [r, g, b], "opacity": a}, transform, thickness, visible.
)doc")
      .def(
          "add_streamlines",
          [](PyScene& s, const py::object& source, const py::object& radius,
             const OptionalTextParameter& colouring, const py::object& color,
             const OptionalTextParameter& value, const py::object& colormap,
             const py::object& opacity, const py::object& stride, const py::object& min_length,
             const OptionalTextParameter& name, const py::kwargs& fields) {
            add_streamlines(s, source, radius, colouring, color, value, colormap, opacity, stride,
                            min_length, name, fields);
          },
          py::arg("source"), py::arg("radius") = 0.5, py::arg("colouring") = py::none(),
          py::arg("color") = py::none(), py::arg("value") = py::none(),
          py::arg("colormap") = py::none(), py::arg("opacity") = 1.0, py::arg("stride") = 1,
          py::arg("min_length") = 0.0, py::arg("name") = py::none(),
          R"doc(Adds a streamlines object: the tractogram drawn as tubes (docs/streamlines.md). `source` is an
intermix.Streamlines, a file path (.trk, .tck, .trx, .tt.gz, .vtk), a source dict
({"file": "cst.tck", "values": ["cst_fa.tsf"]}), or anything intermix.Streamlines takes (a
nibabel Tractogram or ArraySequence, a list of (n, 3) RAS arrays), made one.

radius      tube radius, mm
colouring   the scene's "color_by": "direction" (|dx|, |dy|, |dz| of each segment, the default),
            "streamline_direction", "fixed" (`color`; the default when color is given),
            "point_value" / "streamline_value" (`value` through `colormap`), "group" (TRX)
color       a display (sRGB) colour for "fixed" and for groups without a colour
value       the name of the values to colour by; without `colouring`, point_value or
            streamline_value as the tractogram holds it
colormap    "viridis" (the default), "hot", "gray", ... ; `range=[lo, hi]` maps the values
opacity     per tube crossing, 0..1
stride      every stride-th streamline; min_length: shorter ones (mm) are not drawn
name        the object's name (default: the file's name, else "streamlines", made unique)
Keyword arguments are the object's other keys: range, regions, group_opacity, shading,
transform, thickness, visible.
)doc")
      .def(
          "add_plane",
          [](PyScene& s, const TextParameter& name, const py::kwargs& fields) {
            s.add(text(name, {"Scene.add_plane", "name"}), "plane", py::none(), fields);
          },
          py::arg("name"),
          R"doc(Adds a plane object (an MPR slice when volume= names a volume). Keyword arguments are its keys:
center, normal, up, size, volume, window, colormap, color, opacity.
)doc")
      .def(
          "to_dict", [](const PyScene& s) { return from_document(s.document(), s.sources()); },
          "The scene document as a dict (a copy; Volume and Mesh objects in place, so "
          "Scene.from_dict(scene.to_dict()) is the same scene).")
      .def(
          "copy", [](const PyScene& s) { return std::make_shared<PyScene>(s); },
          "An independent copy sharing the loaded sources.")
      .def("__copy__", [](const PyScene& s) { return std::make_shared<PyScene>(s); })
      .def_property_readonly(
          "names",
          [](const PyScene& s) {
            std::vector<std::string> names;
            for (const ObjectRef& ref : s.scene().order)
              names.push_back(object_name(s.scene(), ref));
            return names;
          },
          "Object names in scene order.")
      .def_property_readonly(
          "notes", [](const PyScene& s) { return s.notes(); },
          "What loading chose for the user (a DICOM series, a mesh file's space), one sentence "
          "each.")
      .def_property_readonly(
          "camera",
          [](const PyScene& s) {
            const Camera& c = s.scene().camera;
            py::dict d;
            d["eye"] = py::make_tuple(c.eye.x, c.eye.y, c.eye.z);
            d["target"] = py::make_tuple(c.target.x, c.target.y, c.target.z);
            d["up"] = py::make_tuple(c.up.x, c.up.y, c.up.z);
            d["fov_deg"] = c.fov_deg;
            d["projection"] =
                c.projection == Projection::orthographic ? "orthographic" : "perspective";
            d["ortho_height"] = c.ortho_height;
            return d;
          },
          "The camera the scene renders with, as a camera block (a \"view\" resolved into eye, "
          "target and up): scene.set(\"camera\", d) gives it back.")
      .def_property_readonly(
          "measurements",
          [](const PyScene& s) {
            py::list out;
            for (const Annotation& a : s.scene_document().annotations())
              out.append(from_document(measurement_json(a, measure(a, s.scene())), {}));
            return out;
          },
          "What each of the scene's \"annotations\" measures, one dict each (kind, label, "
          "points; length_mm, angle_deg, or an ROI's area_mm2, voxels, mean, sd, min, max in the "
          "volume's units), as `intermix info SCENE --annotations --json` gives them.")
      .def_property_readonly(
          "file",
          [](const PyScene& s) -> py::object {
            if (s.file().empty()) return py::none();
            return py::str(s.file().string());
          },
          "The scene file, or None.")
      .def_property_readonly(
          "base_dir", [](const PyScene& s) { return s.base_dir().string(); },
          "The folder relative paths resolve against.")
      .def(
          "render",
          [](const PyScene& s, const OptionalTextParameter& method,
             const OptionalIntParameter& width, const OptionalIntParameter& height,
             const OptionalIntParameter& spp, const OptionalIntParameter& threads,
             const OptionalTextParameter& view_argument, const py::object& colorbar,
             const py::object& colorbar_scale) {
            RenderRequest request =
                render_request("Scene.render", method, width, height, spp, threads);
            request.colorbar = colour_bar_argument(colorbar, {"Scene.render", "colorbar"});
            request.colorbar_scale =
                real_in(colorbar_scale, {"Scene.render", "colorbar_scale"}, 0.25, 8.0);
            const std::optional<std::string> view =
                optional_text(view_argument, {"Scene.render", "view"});
            if (!view) return render_scene(s.scene(), request, nullptr);
            // Framed for the image size rendered: the copy's own image size is set first.
            PyScene viewed = s;
            std::vector<std::pair<std::string, py::object>> size;
            if (request.width) size.emplace_back("image.width", py::int_(*request.width));
            if (request.height) size.emplace_back("image.height", py::int_(*request.height));
            if (!size.empty()) viewed.set(size);
            viewed.look_from(*view);
            return render_scene(viewed.scene(), request, nullptr);
          },
          py::arg("method") = py::none(), py::arg("width") = py::none(),
          py::arg("height") = py::none(), py::arg("spp") = py::none(),
          py::arg("threads") = py::none(), py::arg("view") = py::none(),
          py::arg("colorbar") = false, py::arg("colorbar_scale") = 1.0,
          R"doc(Renders one frame and returns it as an intermix.Image: an (H, W, 4) float32 numpy array of
premultiplied linear RGBA over the scene's background (image.to_uint8() gives the sRGB display
image, as `intermix render` writes it). `method` defaults to the scene's render.method, else "auto" (the fastest method
within reach of the best image for the scene's content; intermix.available_methods()), `width`/`height` to the scene's image size, `spp` (a perfect
square) to the scene's render.spp, else the method's default, and `threads` to all cores.
`view` ("left", "anterior", ...: see set_view) renders with a camera framing the objects from
that direction, leaving the scene's own camera as it is. `colorbar=True` draws a colour bar
for each visible colour-mapped object into the image's top-right corner, as `intermix render
--colorbar` does (FreeType and a DejaVu font; $IMX_FONT names another); a position
("top-left", "bottom-right", "bottom-left", or "outside": beside the image, which grows to the
right) puts them there; `colorbar_scale` (0.25 to 8) sizes their text and strips.

The GIL is released while rendering (other Python threads run, and may render too), and Ctrl-C
cancels the render with KeyboardInterrupt. Raises ValueError for bad arguments and RuntimeError
when the method cannot render the scene. Each call renders from scratch: intermix.Renderer
keeps stages between frames.
)doc")
      .def(
          "_repr_png_", [](const PyScene& s) { return preview_png(s.scene(), 256); },
          "A PNG preview for notebooks: the scene's method at 1 sample per pixel, at most 256 "
          "pixels a side.")
      .def("__repr__", [](const PyScene& s) {
        std::string objects;
        for (const ObjectRef& ref : s.scene().order)
          objects += fmt::format("{}{} ({})", objects.empty() ? "" : ", ",
                                 object_name(s.scene(), ref), object_kind_name(ref.kind));
        return fmt::format("<intermix.Scene {}: {}; {}x{}, method {}>",
                           s.file().empty() ? s.origin() : s.file().string(),
                           objects.empty() ? "no objects" : objects, s.scene().image.width,
                           s.scene().image.height, s.scene().render.method);
      });
}

}  // namespace imx::python
