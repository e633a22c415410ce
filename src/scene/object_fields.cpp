// Parsers for fields that several object types share: shading, thickness, visibility and file
// sources.
#include <cerrno>
#include <system_error>

#include <fmt/format.h>

#include "scene/scene_parsers.hpp"

namespace imx::scene_json {

std::filesystem::path SceneContext::resolve_file(const JsonReader& file) const {
  std::string name = file.string();
  if (name.empty()) file.fail("the file name is empty");
  std::filesystem::path path(name);
  if (path.is_relative() && !base_dir.empty()) path = base_dir / path;
  path = path.lexically_normal();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    file.fail_file(fmt::format("no such file '{}'", path.string()), ENOENT);
  if (std::filesystem::is_directory(path, ec))
    file.fail_file(fmt::format("'{}' is a directory, not a file", path.string()), EISDIR);
  return path;
}

Shading parse_shading(const JsonReader& r) {
  r.check_keys({"enabled", "ambient", "diffuse", "specular", "shininess"});
  Shading s;
  s.enabled = true;
  if (auto v = r.find("enabled")) s.enabled = v->boolean();
  if (auto v = r.find("ambient")) s.ambient = static_cast<float>(v->number(Range::gain()));
  if (auto v = r.find("diffuse")) s.diffuse = static_cast<float>(v->number(Range::gain()));
  if (auto v = r.find("specular")) s.specular = static_cast<float>(v->number(Range::gain()));
  if (auto v = r.find("shininess"))
    s.shininess = static_cast<float>(v->number(Range::closed(0.0, 10000.0)));
  return s;
}

std::optional<double> parse_thickness(const JsonReader& r) {
  if (r.json().is_string()) {
    if (r.string() != "auto")
      r.fail(fmt::format("expected a positive number of mm or \"auto\", got {}", r.describe()));
    return std::nullopt;
  }
  if (!r.json().is_number())
    r.fail(fmt::format("expected a positive number of mm or \"auto\", got {}", r.describe()));
  return r.number(Range::positive());
}

bool parse_visible(const JsonReader& object) {
  if (auto v = object.find("visible")) return v->boolean();
  return true;
}

}  // namespace imx::scene_json

namespace imx {

const std::string& object_name(const Scene& scene, const ObjectRef& ref) {
  const auto i = static_cast<size_t>(ref.index);
  switch (ref.kind) {
    case ObjectKind::volume:
      return scene.volumes.at(i).name;
    case ObjectKind::mesh:
      return scene.meshes.at(i).name;
    case ObjectKind::plane:
      return scene.planes.at(i).name;
    case ObjectKind::streamlines:
      break;
  }
  return scene.streamlines.at(i).name;
}

}  // namespace imx
