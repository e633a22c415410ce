#include "io/zarr/ome_zarr_reader.hpp"

#include <cerrno>
#include <cmath>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "intermix/error.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/json_depth.hpp"
#include "io/voxels/length_units.hpp"
#include "io/voxels/raw_voxels.hpp"
#include "io/zarr/ome_channels.hpp"
#include "io/zarr/zarr_array.hpp"
#include "volume/volume_checks.hpp"

namespace imx::detail {

namespace {

using nlohmann::json;

constexpr uintmax_t kMaxAttributesBytes = 4 << 20;

// One resolution level: its array and where its voxels lie.
struct Level {
  ZarrArray array;
  glm::dvec3 spacing{1.0}, origin{0.0};  // x, y, z
};

// An image's OME metadata (multiscales, omero) and the file it came from.
struct Attrs {
  json doc;
  std::string what;
};

// What the OME layer says about the array's axes.
struct Layout {
  int time_axis = -1, channel_axis = -1;  // index in the array's dimensions, -1 when absent
  size_t ndim = 3;
  std::vector<std::string> dataset_paths, axis_names;
  json multiscale;
  double mm_per_unit[3] = {1.0, 1.0, 1.0};  // x, y, z: what one unit of the axis is in mm
};

// Millimetres in one NGFF space unit (micrometres are usual for microscopes); no unit: mm.
double millimetres_per(const std::string& unit, const std::string& axis, const std::string& what) {
  if (const std::optional<double> mm = millimetres_per_unit(unit)) return *mm;
  throw Error(fmt::format("{}: axis '{}' has unit '{}': read are {}", what, axis, unit,
                          length_units_read()));
}

json read_json(const std::filesystem::path& file) {
  const std::string what = file.string();
  const std::string text = read_zarr_metadata(file, kMaxAttributesBytes);
  if (json_nested_deeper_than(text, 64))
    throw Error(fmt::format("{}: JSON nested deeper than 64 levels", what));
  json doc = json::parse(text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object())
    throw Error(fmt::format("{}: not a JSON object", what));
  return doc;
}

// "name" of an axis: NGFF 0.4 gives objects {"name", "type", "unit"}, 0.3 plain strings.
std::string axis_name(const json& axis, const std::string& what) {
  if (axis.is_string()) return axis.get<std::string>();
  if (axis.is_object() && axis.contains("name") && axis["name"].is_string())
    return axis["name"].get<std::string>();
  throw Error(
      fmt::format("{}: field 'multiscales[0].axes' holds {}, not an axis", what, axis.dump()));
}

Layout parse_layout(const json& attrs, const std::string& what) {
  if (!attrs.contains("multiscales") || !attrs["multiscales"].is_array() ||
      attrs["multiscales"].empty() || !attrs["multiscales"][0].is_object())
    throw Error(fmt::format("{}: missing field 'multiscales' (not an OME-Zarr image)", what));
  Layout l;
  l.multiscale = attrs["multiscales"][0];
  const json& ms = l.multiscale;
  // No axes: NGFF 0.1 and 0.2, whose images are always 5-D.
  std::vector<std::string> names = {"t", "c", "z", "y", "x"};
  if (ms.contains("axes")) {
    if (!ms["axes"].is_array())
      throw Error(fmt::format("{}: field 'multiscales[0].axes' is not a list", what));
    names.clear();
    for (const json& axis : ms["axes"]) {
      names.push_back(axis_name(axis, what));
      const char* spatial[] = {"x", "y", "z"};
      for (int a = 0; a < 3; ++a)
        if (names.back() == spatial[a] && axis.is_object() && axis.contains("unit") &&
            axis["unit"].is_string())
          l.mm_per_unit[a] = millimetres_per(axis["unit"].get<std::string>(), spatial[a], what);
    }
  }
  std::string joined;
  for (const std::string& n : names) joined += (joined.empty() ? "" : ",") + n;
  const size_t n = names.size();
  if (n < 3 || n > 5 || names[n - 3] != "z" || names[n - 2] != "y" || names[n - 1] != "x")
    throw Error(
        fmt::format("{}: field 'multiscales[0].axes' is [{}]: only t and c followed by "
                    "z, y, x are read",
                    what, joined));
  l.ndim = n;
  l.axis_names = names;
  for (size_t d = 0; d + 3 < n; ++d) {
    if (names[d] == "t" && l.time_axis < 0)
      l.time_axis = static_cast<int>(d);
    else if (names[d] == "c" && l.channel_axis < 0)
      l.channel_axis = static_cast<int>(d);
    else
      throw Error(
          fmt::format("{}: field 'multiscales[0].axes' is [{}]: only t and c followed by "
                      "z, y, x are read",
                      what, joined));
  }
  if (!ms.contains("datasets") || !ms["datasets"].is_array() || ms["datasets"].empty())
    throw Error(fmt::format("{}: missing field 'multiscales[0].datasets'", what));
  for (const json& ds : ms["datasets"]) {
    if (!ds.is_object() || !ds.contains("path") || !ds["path"].is_string())
      throw Error(fmt::format("{}: field 'multiscales[0].datasets' holds {} with no 'path'", what,
                              ds.dump().substr(0, 80)));
    const std::string path = ds["path"].get<std::string>();
    if (path.empty() || path.find("..") != std::string::npos || path[0] == '/')
      throw Error(
          fmt::format("{}: dataset path '{}' is not a folder inside the image", what, path));
    l.dataset_paths.push_back(path);
  }
  return l;
}

// Applies a coordinateTransformations list (scale, then translation) to `spacing` and `origin`
// (array order: one number per axis).
void apply_transforms(const json& list, std::vector<double>& scale, std::vector<double>& shift,
                      const std::string& field, const std::string& what) {
  if (!list.is_array()) throw Error(fmt::format("{}: field '{}' is not a list", what, field));
  for (const json& t : list) {
    const std::string type = t.is_object() && t.contains("type") && t["type"].is_string()
                                 ? t["type"].get<std::string>()
                                 : "";
    if (type == "identity") continue;
    if (type != "scale" && type != "translation")
      throw Error(
          fmt::format("{}: field '{}' holds transformation {}: only scale and translation "
                      "are read",
                      what, field, t.dump().substr(0, 80)));
    if (!t.contains(type))
      throw Error(
          fmt::format("{}: field '{}': a {} with no '{}' list (a 'path' to a file is not "
                      "read)",
                      what, field, type, type));
    const json& v = t[type];
    if (!v.is_array() || v.size() != scale.size())
      throw Error(fmt::format("{}: field '{}': {} {} must hold {} numbers", what, field, type,
                              v.dump().substr(0, 80), scale.size()));
    for (size_t d = 0; d < scale.size(); ++d) {
      if (!v[d].is_number() || !std::isfinite(v[d].get<double>()))
        throw Error(fmt::format("{}: field '{}': {} {} holds a value that is not a finite number",
                                what, field, type, v.dump().substr(0, 80)));
      const double x = v[d].get<double>();
      if (type == "scale") {
        if (x <= 0)
          throw Error(fmt::format("{}: field '{}': scale {} must be positive", what, field,
                                  v.dump().substr(0, 80)));
        scale[d] *= x;
        shift[d] *= x;
      } else {
        shift[d] += x;
      }
    }
  }
}

Level open_level(const std::filesystem::path& dir, const Attrs& attrs, int level,
                 Layout* layout_out = nullptr) {
  const std::string& what = attrs.what;
  const Layout layout = parse_layout(attrs.doc, what);
  if (level < 0 || static_cast<size_t>(level) >= layout.dataset_paths.size())
    throw Error(fmt::format("{}: level {} requested, the image has {} (0 to {})", dir.string(),
                            level, layout.dataset_paths.size(), layout.dataset_paths.size() - 1));
  Level l{read_zarr_array(dir / layout.dataset_paths[level])};
  const size_t n = l.array.shape.size();
  if (n != layout.ndim)
    throw Error(fmt::format("{}: {} dimensions, but multiscales[0].axes names {}", l.array.what, n,
                            layout.ndim));
  // NGFF 0.5: a v3 array's dimension_names are the axes' names.
  for (size_t d = 0; d < l.array.dimension_names.size(); ++d)
    if (l.array.dimension_names[d] != layout.axis_names[d])
      throw Error(fmt::format(
          "{}: field 'dimension_names' names dimension {} '{}', multiscales[0].axes names it '{}'",
          l.array.what, d, l.array.dimension_names[d], layout.axis_names[d]));
  std::vector<double> scale(n, 1.0), shift(n, 0.0);
  const json& ds = layout.multiscale["datasets"][level];
  if (ds.contains("coordinateTransformations"))
    apply_transforms(ds["coordinateTransformations"], scale, shift,
                     fmt::format("multiscales[0].datasets[{}].coordinateTransformations", level),
                     what);
  if (layout.multiscale.contains("coordinateTransformations"))
    apply_transforms(layout.multiscale["coordinateTransformations"], scale, shift,
                     "multiscales[0].coordinateTransformations", what);
  for (int a = 0; a < 3; ++a) {
    l.spacing[a] = scale[n - 1 - a] * layout.mm_per_unit[a];
    l.origin[a] = shift[n - 1 - a] * layout.mm_per_unit[a];
  }
  if (layout_out) *layout_out = layout;
  return l;
}

// OME-NGFF 0.4 says nothing of anatomical orientation: the x, y, z axes are taken as the index
// axes with the file's spacing and origin, the identity direction (as NiiVue shows them). A file
// intermix wrote from an oriented grid (a flip, an oblique or tilted grid) keeps that grid's
// whole matrix under "intermix": each level is placed by it through NGFF's scale and
// translation of the level against level 0's.
glm::dmat4 placement(const std::filesystem::path& dir, const Attrs& attrs, const Level& l) {
  glm::dmat4 m(1.0);
  for (int a = 0; a < 3; ++a) {
    m[a][a] = l.spacing[a];
    m[3][a] = l.origin[a];
  }
  const auto own = attrs.doc.find("intermix");
  if (own == attrs.doc.end()) return m;
  const std::string& what = attrs.what;
  const json* rows =
      own->is_object() && own->contains("index_to_world") ? &(*own)["index_to_world"] : nullptr;
  glm::dmat4 oriented(1.0);
  bool valid = rows && rows->is_array() && rows->size() == 4;
  for (int r = 0; valid && r < 4; ++r) {
    const json& row = (*rows)[r];
    valid = row.is_array() && row.size() == 4;
    for (int c = 0; valid && c < 4; ++c) {
      valid = row[c].is_number();
      if (valid) oriented[c][r] = row[c].get<double>();
    }
  }
  if (!valid || oriented[0][3] != 0.0 || oriented[1][3] != 0.0 || oriented[2][3] != 0.0 ||
      oriented[3][3] != 1.0)
    throw Error(
        fmt::format("{}: field 'intermix.index_to_world' is not 4 rows of 4 numbers "
                    "ending 0 0 0 1",
                    what));
  const Level first = open_level(dir, attrs, 0);
  glm::dmat4 to_first(1.0);
  for (int a = 0; a < 3; ++a) {
    to_first[a][a] = l.spacing[a] / first.spacing[a];
    to_first[3][a] = (l.origin[a] - first.origin[a]) / first.spacing[a];
  }
  return oriented * to_first;
}

glm::ivec3 grid_dims(const ZarrArray& a) {
  const size_t n = a.shape.size();
  const glm::ivec3 dims(static_cast<int>(a.shape[n - 1]), static_cast<int>(a.shape[n - 2]),
                        static_cast<int>(a.shape[n - 3]));
  if (static_cast<double>(dims.x) * dims.y * dims.z > static_cast<double>(kMaxGridVoxels))
    throw Error(fmt::format("{}: field 'shape': a grid of {}x{}x{} voxels, more than {}", a.what,
                            dims.x, dims.y, dims.z, kMaxGridVoxels));
  return dims;
}

// The image's OME attributes and the file holding them: NGFF 0.4's .zattrs (Zarr v2), or NGFF
// 0.5's zarr.json (Zarr v3) group "attributes"."ome", whose multiscales and omero are 0.4's.
Attrs read_attrs(const std::filesystem::path& dir) {
  std::error_code ec;
  require_input_folder(dir);  // "is a FIFO (named pipe), not a folder", a link loop, ...
  const std::filesystem::path v2 = dir / ".zattrs", v3 = dir / "zarr.json";
  if (std::filesystem::exists(v2, ec)) return {read_json(v2), v2.string()};
  if (!std::filesystem::exists(v3, ec))
    throw Error(fmt::format("{}: no .zattrs or zarr.json (not an OME-Zarr image)", dir.string()));
  const std::string what = v3.string();
  const json doc = read_json(v3);
  if (doc.value("zarr_format", json()) != 3)
    throw Error(fmt::format("{}: field 'zarr_format' is not 3", what));
  if (doc.value("node_type", json()) != "group")
    throw Error(fmt::format(
        "{}: field 'node_type' is {}: an OME-Zarr image is a group (its levels are arrays)", what,
        doc.value("node_type", json()).dump().substr(0, 40)));
  const json attributes = doc.value("attributes", json::object());
  const json ome = attributes.is_object() ? attributes.value("ome", json()) : json();
  if (!ome.is_object())
    throw Error(
        fmt::format("{}: missing field 'attributes.ome' (not an OME-Zarr 0.5 image)", what));
  return {ome, what};
}

}  // namespace

bool is_zarr_folder(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return false;
  for (const char* name : {".zgroup", ".zattrs", ".zarray", "zarr.json"})
    if (std::filesystem::exists(dir / name, ec)) return true;
  return false;
}

VolumeHeader read_ome_zarr_header(const std::filesystem::path& dir, int level) {
  Layout layout;
  const Attrs attrs = read_attrs(dir);
  const Level l = open_level(dir, attrs, level, &layout);
  VolumeHeader h;
  h.dims = grid_dims(l.array);
  h.type = storage_type_for(l.array.type);
  h.index_to_world = placement(dir, attrs, l);
  h.frames = layout.time_axis < 0 ? 1 : static_cast<int>(l.array.shape[layout.time_axis]);
  return h;
}

int read_ome_zarr_level_count(const std::filesystem::path& dir) {
  Layout layout;
  open_level(dir, read_attrs(dir), 0, &layout);
  return static_cast<int>(layout.dataset_paths.size());
}

VolumeData read_ome_zarr(const std::filesystem::path& dir, int level, int frame, int channel) {
  return read_ome_zarr_region(dir, {}, level, frame, channel);
}

VolumeData read_ome_zarr_region(const std::filesystem::path& dir, const VoxelBox& asked, int level,
                                int frame, int channel) {
  Layout layout;
  const Attrs attrs = read_attrs(dir);
  const Level l = open_level(dir, attrs, level, &layout);
  const ZarrArray& a = l.array;
  std::vector<int64_t> lead(a.shape.size() - 3, 0);
  const auto pick = [&](int axis, int value, const char* name) {
    const int64_t count = axis < 0 ? 1 : a.shape[axis];
    if (value < 0 || value >= count)
      throw Error(fmt::format("{}: {} {} requested, the image has {} (0 to {})", dir.string(), name,
                              value, count, count - 1));
    if (axis >= 0) lead[axis] = value;
  };
  pick(layout.time_axis, frame, "frame");
  pick(layout.channel_axis, channel, "channel");
  const glm::ivec3 dims = grid_dims(a);
  // An empty box (read_ome_zarr's): the whole grid.
  const VoxelBox box = asked.empty() ? VoxelBox::whole(dims) : asked;
  require_box_inside(dims, box, dir.string());
  require_loadable_box(box, a.what);
  VolumeData v;
  v.dims = box.size();
  v.index_to_world = box_index_to_world(placement(dir, attrs, l), box.lo);
  v.voxels = load_voxels(a.type, box.count(), a.big_endian, a.what,
                         [&](std::span<uint8_t> bytes) { read_zarr_block(a, lead, box, bytes); });
  v.validate(a.what);
  return v;
}

std::vector<OmeChannel> read_ome_zarr_channels(const std::filesystem::path& dir) {
  const Attrs attrs = read_attrs(dir);
  Layout layout;
  const Level l = open_level(dir, attrs, 0, &layout);
  const int count =
      layout.channel_axis < 0 ? 1 : static_cast<int>(l.array.shape[layout.channel_axis]);
  return parse_ome_channels(attrs.doc.value("omero", json()), count, attrs.what);
}

}  // namespace imx::detail
