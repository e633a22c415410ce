// load_scene / parse_scene: JSON text -> overrides -> validated Scene.
#include <cerrno>
#include <fstream>
#include <sstream>
#include <system_error>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "intermix/error.hpp"
#include "intermix/scene.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"
#include "scene/mesh_overlay.hpp"
#include "scene/scene_document.hpp"
#include "scene/scene_parsers.hpp"
#include "scene/strict_json.hpp"
#include "scene/world_space.hpp"

namespace imx {
namespace {

using scene_json::JsonReader;

// nlohmann's messages start with "[json.exception.parse_error.101] ": keep the readable part.
std::string readable(const std::string& what) {
  size_t close = what.find("] ");
  return what.rfind("[json.exception.", 0) == 0 && close != std::string::npos
             ? what.substr(close + 2)
             : what;
}

// Checks a name for use in --set paths and plane references.
void check_name(const JsonReader& r, const std::string& name) {
  if (name.empty()) r.fail("the name is empty");
  if (name.find_first_of(".[]=") != std::string::npos)
    r.fail(fmt::format("{} may not contain '.', '[', ']' or '=' (they separate --set paths)",
                       r.text()));
  if (name.find_first_not_of("0123456789") == std::string::npos)
    r.fail(fmt::format("{} is all digits, which --set would read as an index", r.text()));
}

}  // namespace

Scene scene_json::parse_scene_document(const nlohmann::json& root, const std::string& origin,
                                       scene_json::SceneContext& context) {
  JsonReader r(root, origin);
  r.check_keys({"description", "space", "camera", "image", "lights", "objects", "csg", "render",
                "annotations"});
  Scene scene;
  if (auto v = r.find("description")) v->string();
  // The scene's world: what its points, directions and inline transforms are given in.
  context.world_space = MeshSpace::lps;
  if (auto v = r.find("space"))
    context.world_space = v->choice({"LPS", "RAS"}) == "RAS" ? MeshSpace::ras : MeshSpace::lps;
  // No camera, or a camera with a "view": framed around the objects once they are read.
  std::optional<PatientView> view;
  if (auto v = r.find("camera"))
    scene.camera = scene_json::parse_camera(*v, &view, context.world_space);
  else
    view = PatientView::anterior;
  if (auto v = r.find("image")) scene.image = scene_json::parse_image(*v);
  context.image_rows = scene.image.height;
  if (auto v = r.find("lights")) scene.lights = scene_json::parse_lights(*v, context.world_space);
  if (auto v = r.find("render")) scene.render = scene_json::parse_render(*v);

  // First every name and type, so that planes may name volumes listed after them.
  const std::vector<JsonReader> objects = r.get("objects").elements();
  std::map<std::string, std::string> types;
  std::map<std::string, size_t> first_use;
  std::vector<std::string> kinds;
  for (size_t i = 0; i < objects.size(); ++i) {
    const JsonReader& o = objects[i];
    o.expect_object();
    JsonReader name_reader = o.get("name");
    std::string name = name_reader.string();
    check_name(name_reader, name);
    if (auto [it, fresh] = first_use.emplace(name, i); !fresh)
      name_reader.fail(
          fmt::format("{} is already the name of objects[{}]", name_reader.text(), it->second));
    kinds.push_back(o.get("type").choice({"volume", "mesh", "plane", "streamlines", "connectome"}));
    types[name] = kinds.back();
  }

  context.used.clear();
  context.automatic_looks.clear();
  context.mesh_space_candidates.clear();
  for (size_t i = 0; i < objects.size(); ++i)
    if (kinds[i] == "volume")
      scene.volumes.push_back(scene_json::parse_volume_object(objects[i], context));
  std::vector<ObjectRef> order;
  int volume_index = 0;
  for (size_t i = 0; i < objects.size(); ++i) {
    if (kinds[i] == "volume") {
      order.push_back({ObjectKind::volume, volume_index++});
    } else if (kinds[i] == "mesh") {
      order.push_back({ObjectKind::mesh, static_cast<int>(scene.meshes.size())});
      scene.meshes.push_back(scene_json::parse_mesh_object(objects[i], context));
    } else if (kinds[i] == "streamlines") {
      order.push_back({ObjectKind::streamlines, static_cast<int>(scene.streamlines.size())});
      scene.streamlines.push_back(scene_json::parse_streamline_object(objects[i], context));
    } else if (kinds[i] == "connectome") {  // spheres and tubes: a streamline object's kind
      order.push_back({ObjectKind::streamlines, static_cast<int>(scene.streamlines.size())});
      scene.streamlines.push_back(scene_json::parse_connectome_object(objects[i], context));
    } else {
      order.push_back({ObjectKind::plane, static_cast<int>(scene.planes.size())});
      scene.planes.push_back(
          scene_json::parse_plane_object(objects[i], scene, types, context.world_space));
    }
  }
  scene.order = std::move(order);
  scene_json::apply_color_by(objects, scene, context, types);
  scene_json::parse_clip_meshes(objects, scene);
  std::optional<JsonReader> csg = r.find("csg");
  if (csg) scene.csg = scene_json::parse_csg(*csg, scene);
  // "csg": null keeps the interiors a CSG file declares: it is the file's baseline without CSG.
  if (!(csg && csg->json().is_null())) scene_json::check_interiors(objects, scene);
  std::optional<JsonReader> render = r.find("render");
  if (render) {
    scene_json::check_last_volume(*render, scene, types);
    scene_json::check_mixing_priority(*render, scene, types);
  }
  context.annotations.clear();
  if (auto v = r.find("annotations"))
    context.annotations = scene_json::parse_annotations(*v, scene, types, context.world_space);
  if (view) {
    scene.camera = framed_camera(scene.camera, visible_bounds(scene, bool(context.region)), *view,
                                 static_cast<double>(scene.image.width) / scene.image.height);
    // In the scene's own space (to_lps undoes itself).
    const glm::dvec3 centre = scene_json::to_lps(scene.camera.target, context.world_space);
    if (!r.has("camera"))
      context.notes.push_back(fmt::format(
          "no camera: looking from the anterior at the objects' centre [{:.1f}, {:.1f}, {:.1f}] "
          "from {:.0f} mm",
          centre.x, centre.y, centre.z, glm::length(scene.camera.eye - scene.camera.target)));
  }
  for (std::string& note :
       scene_json::mirrored_mesh_notes(context.mesh_space_candidates, scene.volumes))
    context.notes.push_back(std::move(note));
  context.mesh_space_candidates.clear();
  // A CSG scene is meant for the csg method unless it asks for another (CSG.md §4.2).
  if (scene.csg && !(render && render->has("method"))) scene.render.method = "csg";
  scene.notes = std::move(context.notes);
  context.notes.clear();
  return scene;
}

nlohmann::json scene_json::parse_scene_json(const std::string& json_text,
                                            const std::string& origin) {
  nlohmann::json root;
  try {
    root = scene_json::parse_strict_json(json_text, origin);
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("{}: invalid JSON: {}", origin, readable(e.what())));
  }
  if (!root.is_object())
    throw Error(fmt::format("{}: expected a JSON object at the top level, got {}", origin,
                            root.type_name()));
  return root;
}

std::string scene_json::read_scene_file(const std::filesystem::path& file) {
  require_regular_file(file);
  std::ifstream in = open_input_stream(file, file.string());
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

Scene parse_scene(const std::string& json_text, const std::filesystem::path& base_dir,
                  const std::string& origin, const std::vector<std::string>& overrides) {
  return SceneDocument::from_text(json_text, origin, base_dir, overrides).take_scene();
}

Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
  return SceneDocument::load(file, overrides).take_scene();
}

Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides,
                 const VolumeRegionChooser& region) {
  return SceneDocument::load(file, overrides, region).take_scene();
}

}  // namespace imx
