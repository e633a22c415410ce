// Parser for a "volume" object: its source, placement, style, transfer function and clipping.
#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <system_error>

#include <fmt/format.h>

#include "intermix/io.hpp"
#include "scene/edit_distance.hpp"
#include "scene/scene_parsers.hpp"

namespace imx::detail {
namespace {

constexpr int kDefaultPhantomSize = 128;

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// Loads (or reuses) the volume a "source" names; errors from the readers get the JSON path.
std::shared_ptr<const VolumeData> load_volume_source(const JsonReader& src, SceneContext& context) {
  src.check_keys({"phantom", "size", "file"});
  const bool phantom = src.has("phantom"), file = src.has("file");
  if (phantom == file)
    src.fail(phantom ? "give either \"phantom\" or \"file\", not both"
                     : "needs \"phantom\" (a built-in volume) or \"file\"");
  std::string key, what;
  std::function<VolumeData()> load;
  JsonReader culprit = src;
  if (phantom) {
    JsonReader name_reader = src.get("phantom");
    std::string name = name_reader.string();
    std::vector<std::string> names = phantom_names();
    if (std::find(names.begin(), names.end(), name) == names.end())
      name_reader.fail(fmt::format("{} is not a built-in phantom{}; they are: {}",
                                   name_reader.text(), did_you_mean(name, names), join(names)));
    int size = kDefaultPhantomSize;
    if (auto v = src.find("size")) size = v->integer(8, 1024);
    key = fmt::format("phantom:{}:{}", name, size);
    what = fmt::format("phantom '{}' of size {}", name, size);
    load = [name, size] { return make_phantom(name, size); };
  } else {
    if (auto v = src.find("size")) v->fail("only phantoms have a size");
    culprit = src.get("file");
    std::filesystem::path path = context.resolve_file(culprit);
    std::error_code ec;
    std::filesystem::path canonical = std::filesystem::weakly_canonical(path, ec);
    key = "file:" + (ec ? path : canonical).string();
    what = path.string();
    load = [path] { return read_volume(path); };
  }
  if (auto it = context.volumes.find(key); it != context.volumes.end()) return it->second;
  std::shared_ptr<const VolumeData> data;
  try {
    VolumeData volume = load();
    volume.validate(what);
    data = std::make_shared<const VolumeData>(std::move(volume));
  } catch (const std::exception& e) {
    culprit.fail(e.what());
  }
  context.volumes.emplace(key, data);
  return data;
}

TransferFunction parse_transfer_function(const JsonReader& r) {
  r.check_keys({"points", "unit_distance"});
  TransferFunction tf;
  JsonReader points = r.get("points");
  if (points.size() == 0) points.fail("needs at least one point [value, r, g, b, a]");
  for (const JsonReader& p : points.elements()) {
    if (!p.json().is_array() || p.json().size() != 5)
      p.fail("expected a point [value, r, g, b, a], got " + p.describe());
    TfPoint point;
    point.value = p.at(0).number();
    for (int c = 0; c < 4; ++c)
      point.rgba[c] =
          static_cast<float>(p.at(static_cast<size_t>(c) + 1).number(Range::closed(0.0, 1.0)));
    if (!tf.points.empty() && point.value < tf.points.back().value)
      p.at(0).fail(
          fmt::format("value {} is below the previous point's {} (points must be sorted "
                      "by value)",
                      point.value, tf.points.back().value));
    tf.points.push_back(point);
  }
  // The table is indexed in float: the whole span must be a finite float too.
  if (!std::isfinite(static_cast<float>(tf.points.back().value) -
                     static_cast<float>(tf.points.front().value)))
    points.fail(fmt::format("the values span [{}, {}], wider than a float can hold",
                            tf.points.front().value, tf.points.back().value));
  if (auto v = r.find("unit_distance")) tf.unit_distance = v->number(Range::length());
  return tf;
}

std::vector<ClipPlane> parse_clip_planes(const JsonReader& r) {
  std::vector<ClipPlane> planes;
  for (const JsonReader& e : r.elements()) {
    e.check_keys({"point", "normal"});
    ClipPlane plane;
    plane.point = e.get("point").vec3(Range::coordinate());
    plane.normal = e.get("normal").direction();
    planes.push_back(plane);
  }
  return planes;
}

}  // namespace

VolumeObject parse_volume_object(const JsonReader& r, SceneContext& context) {
  r.check_keys({"name", "type", "source", "transform", "style", "iso_value", "transfer_function",
                "shading", "clip_planes", "clip"});
  VolumeObject v;
  v.name = r.get("name").string();
  glm::dmat4 transform(1.0);
  if (auto t = r.find("transform")) transform = parse_transform(*t);
  if (auto s = r.find("style")) {
    std::string style = s->choice({"dvr", "iso", "mip", "xray"});
    v.style = style == "dvr"   ? VolumeStyle::dvr
              : style == "iso" ? VolumeStyle::iso
              : style == "mip" ? VolumeStyle::mip
                               : VolumeStyle::xray;
  }
  if (auto iso = r.find("iso_value"))
    v.iso_value = iso->number();
  else if (v.style == VolumeStyle::iso)
    r.fail("missing required key 'iso_value' (the style is iso)");
  if (auto tf = r.find("transfer_function")) {
    v.transfer_function = parse_transfer_function(*tf);
  } else if (v.style == VolumeStyle::iso) {
    v.transfer_function.points = {TfPoint{v.iso_value, glm::vec4(1.0f)}};  // white, opaque
  } else {
    r.fail("missing required key 'transfer_function' (needed by every style but iso)");
  }
  if (auto s = r.find("shading")) v.shading = parse_shading(*s);
  if (auto c = r.find("clip_planes")) v.clip_planes = parse_clip_planes(*c);
  // "clip" names meshes, which come later in the file: parse_clip_meshes reads it.
  // The source last: reading a large file is the slowest step, so cheap errors come first.
  v.data = load_volume_source(r.get("source"), context);
  v.index_to_world = transform * v.data->index_to_world;
  return v;
}

}  // namespace imx::detail
