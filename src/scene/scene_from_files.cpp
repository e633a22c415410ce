#include "scene/scene_from_files.hpp"

#include "scene/automatic_look.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "io/overlay/cifti.hpp"
#include "io/overlay/vertex_overlay.hpp"
#include "io/overlay/volume_overlay.hpp"
#include "io/streamlines/streamline_formats.hpp"
#include "io/streams/regular_file.hpp"
#include "io/voxels/nifti_header.hpp"
#include "io/zarr/ome_zarr_reader.hpp"

#include <set>
#include <system_error>

#include <fmt/format.h>

#include "intermix/dicom.hpp"
#include "intermix/error.hpp"
#include "intermix/formats.hpp"
#include "intermix/io.hpp"
#include "scene/overrides.hpp"
#include "scene/scene_document.hpp"

namespace imx {
namespace {

using Json = nlohmann::json;

constexpr const char* kOrigin = "scene from files";

// An object name from a file's name: "FLAIR.nii.gz" -> "FLAIR", a folder by its own name, with
// the characters --set paths reserve replaced, and a number added when it is taken.
std::string object_name(const std::filesystem::path& file, std::set<std::string>& taken) {
  std::filesystem::path p = file;
  if (p.filename().empty()) p = p.parent_path();  // "CT/"
  std::string name = p.filename().string();
  for (const char* ext : {".gz", ".nii", ".nrrd", ".nhdr", ".mha", ".mhd", ".mgh", ".mgz", ".hdr",
                          ".img", ".dcm", ".ply", ".stl", ".obj", ".gii", ".off"})
    if (name.size() > std::string(ext).size() && name.ends_with(ext))
      name.resize(name.size() - std::string(ext).size());
  for (char& c : name)
    if (c == '.' || c == '[' || c == ']' || c == '=' || c == ' ') c = '_';
  if (name.empty() || name.find_first_not_of("0123456789") == std::string::npos)
    name = "object" + name;
  std::string unique = name;
  for (int n = 2; taken.contains(unique); ++n) unique = fmt::format("{}_{}", name, n);
  taken.insert(unique);
  return unique;
}

Json color_json(const glm::vec3& c) {
  return Json::array({c.r, c.g, c.b});
}

// Volumes that are segmentations become label volumes: a 3D Slicer .seg.nrrd through its own
// segment fields, any other label map (looks_like_label_map) in the default palette (a saved
// scene shows the choice). A volume the user's overrides gave a transfer function or a style
// stays as it is, and so does a channel of an OME-Zarr image.
void mark_label_maps(SceneDocument& read) {
  const Json& objects = read.json()["objects"];
  std::vector<size_t> labels;
  for (size_t k = 0; k < objects.size(); ++k) {
    const Json& o = objects[k];
    if (o["type"] != "volume" || o.contains("transfer_function") || o.contains("style")) continue;
    if (o["source"].contains("channel")) continue;  // microscopy: its channel's colour and window
    const ObjectRef ref = read.scene().order[k];
    if (looks_like_label_map(*read.scene().volumes[static_cast<size_t>(ref.index)].data))
      labels.push_back(k);
  }
  if (labels.empty()) return;
  read.edit([&](Json& document) {
    for (size_t k : labels) {
      Json& o = document["objects"][k];
      o["style"] = "labels";
      const std::string file = o["source"]["file"].get<std::string>();
      if (file.size() > 9 && file.compare(file.size() - 9, 9, ".seg.nrrd") == 0)
        o["labels"] = {{"file", file}};
    }
  });
}

// An overlay file's colouring: a label overlay its own table; signed values (curvature, sulcal
// depth, a statistic) cold-hot both ways over the 98th percentile of their magnitude; others
// (thickness) viridis over their 2nd to 98th percentile.
Json automatic_coloring(Json overlay, const detail::VertexOverlay& read) {
  if (read.labels) return overlay;
  std::vector<double> values;
  for (double v : read.values)
    if (std::isfinite(v)) values.push_back(v);
  if (values.empty() && !read.values.empty())
    throw Error(
        fmt::format("{}: none of its {} values is a number (all are NaN or infinite): "
                    "nothing to colour the surface by",
                    overlay["file"].get<std::string>(), read.values.size()));
  if (values.empty()) return overlay;  // the loader names what is missing
  auto quantile = [](std::vector<double> v, double q) {
    const auto at = v.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
    std::nth_element(v.begin(), at, v.end());
    return *at;
  };
  const double lo = quantile(values, 0.02), hi = quantile(values, 0.98);
  if (lo < 0.0 && hi > 0.0) {
    std::vector<double> magnitude(values.size());
    std::transform(values.begin(), values.end(), magnitude.begin(),
                   [](double v) { return std::abs(v); });
    const double top = std::max(quantile(magnitude, 0.98), 1e-12);
    overlay["colormap"] = "cold-hot";
    overlay["range"] = {0.0, top};
    overlay["symmetric"] = true;
  } else {
    overlay["colormap"] = "viridis";
    overlay["range"] = {lo, hi > lo ? hi : lo + 1.0};
  }
  return overlay;
}

Json automatic_overlay(const std::filesystem::path& file) {
  return automatic_coloring({{"file", file.string()}}, detail::read_vertex_overlay(file));
}

std::filesystem::path mesh_file_of(const Json& mesh) {
  return mesh["source"]["file"].get<std::string>();
}

// A CIFTI-2 file colours each mesh given right before it that has no overlay yet (both
// hemispheres: intermix render L.surf.gii R.surf.gii x.dscalar.nii), each with the map of the
// structure its file says it is (written out as "structure"); its first map.
void add_cifti_overlays(const std::filesystem::path& file, const std::filesystem::path& absolute,
                        Json& objects) {
  std::vector<size_t> surfaces;
  for (size_t k = objects.size();
       k > 0 && objects[k - 1]["type"] == "mesh" && !objects[k - 1].contains("overlay"); --k)
    surfaces.push_back(k - 1);
  if (surfaces.empty()) throw Error(detail::cifti_needs_surfaces(file.string()));
  const detail::CiftiFile cifti = detail::read_cifti(absolute);
  for (size_t k : surfaces) {
    Json& mesh = objects[k];
    const std::filesystem::path surface = mesh_file_of(mesh);
    const size_t vertices = read_mesh_file(surface).info.file_vertices;
    const std::string structure = detail::cifti_structure_of_surface(cifti, surface, vertices);
    Json overlay = {{"file", absolute.string()},
                    {"structure", detail::short_structure_name(structure)}};
    if (cifti.maps > 1) overlay["frame"] = 0;
    mesh["overlay"] =
        automatic_coloring(overlay, detail::cifti_overlay(cifti, structure, 0, file.string()));
  }
}

// A FreeSurfer per-vertex map stored as a volume (lh.thickness.mgh, sig.nii.gz) given right
// after its surface: as many voxels as the surface has vertices, and an axis of 1
// (is_vertex_volume_shape), which no brain image has. Its overlay, else nullopt (a volume).
std::optional<Json> vertex_volume_overlay(const std::filesystem::path& file,
                                          const std::filesystem::path& absolute,
                                          const Json& objects) {
  if (objects.empty() || objects.back()["type"] != "mesh" || objects.back().contains("overlay") ||
      is_dicom_source(file) || !is_volume_file(file))
    return std::nullopt;
  const VolumeHeader header = read_volume_header(absolute);
  const glm::ivec3 d = header.dims;
  if (std::min({d.x, d.y, d.z}) != 1) return std::nullopt;  // a 3-D image: never an overlay
  const size_t vertices = read_mesh_file(mesh_file_of(objects.back())).info.file_vertices;
  if (!detail::is_vertex_volume_shape(d, vertices)) return std::nullopt;
  Json overlay = {{"file", absolute.string()}};
  if (header.frames > 1) overlay["frame"] = 0;
  return automatic_coloring(
      overlay, detail::volume_as_overlay(read_volume(absolute, 0), vertices, file.string()));
}

// A multi-channel OME-Zarr image: one volume per active channel (every channel when none is),
// named by its label, each drawn in its colour and window (channel_look.hpp); else nullopt.
std::optional<Json> channel_objects(const std::filesystem::path& file,
                                    const std::filesystem::path& absolute,
                                    std::set<std::string>& taken) {
  if (!detail::is_zarr_folder(file)) return std::nullopt;
  const std::vector<detail::OmeChannel> channels = detail::read_ome_zarr_channels(absolute);
  if (channels.size() < 2) return std::nullopt;
  const bool any_active = std::any_of(channels.begin(), channels.end(),
                                      [](const detail::OmeChannel& c) { return c.active; });
  Json objects = Json::array();
  for (size_t c = 0; c < channels.size(); ++c)
    if (channels[c].active || !any_active)
      objects.push_back({{"name", object_name(channels[c].label, taken)},
                         {"type", "volume"},
                         {"source", {{"file", absolute.string()}, {"channel", c}}}});
  return objects;
}

}  // namespace

const std::vector<glm::vec3>& mesh_palette() {
  // Distinct, light enough to shade, none of them grey (a CT's own colour).
  static const std::vector<glm::vec3> palette = {
      {0.90f, 0.75f, 0.35f}, {0.85f, 0.35f, 0.30f}, {0.35f, 0.60f, 0.90f}, {0.45f, 0.80f, 0.45f},
      {0.80f, 0.50f, 0.85f}, {0.95f, 0.60f, 0.20f}, {0.40f, 0.85f, 0.85f}, {0.90f, 0.55f, 0.65f}};
  return palette;
}

SceneDocument scene_from_files(const std::vector<std::filesystem::path>& files,
                               const std::string& view, const std::vector<std::string>& overrides,
                               const VolumeRegionChooser& region, bool coarse_levels) {
  if (files.empty()) throw Error(fmt::format("{}: no files given", kOrigin));
  Json objects = Json::array();
  std::set<std::string> taken;
  size_t meshes = 0;
  std::optional<size_t> last_mesh;         // an overlay file colours the mesh before it
  std::optional<size_t> last_streamlines;  // a .tsf holds values of the tractogram before it
  size_t last_nodes = SIZE_MAX;  // a BrainNet .edge: edges of the .node object just before it
  for (const std::filesystem::path& file : files) {
    std::error_code ec;
    if (!std::filesystem::is_directory(file, ec)) {
      // Each file is told apart by its bytes below: a FIFO or device must be refused first.
      try {
        require_regular_file(file);
      } catch (const FileError& e) {
        // A dangling link keeps the guarded open's message, which says where it points.
        if (e.code() != ENOENT ||
            std::filesystem::is_symlink(std::filesystem::symlink_status(file, ec)))
          throw;
        throw FileError(fmt::format("{}: no such file or folder", file.string()), ENOENT);
      }
    }
    const std::filesystem::path absolute = std::filesystem::absolute(file, ec).lexically_normal();
    // Surface data in volume containers: CIFTI-2, FreeSurfer's per-vertex NIfTI and MGH files.
    if (!is_dicom_source(file) && detail::is_cifti(file)) {
      add_cifti_overlays(file, absolute, objects);
      continue;
    }
    if (std::optional<Json> overlay = vertex_volume_overlay(file, absolute, objects)) {
      objects.back()["overlay"] = std::move(*overlay);
      continue;
    }
    if (!is_dicom_source(file) && !is_volume_file(file) && detail::is_overlay_file(file)) {
      if (!last_mesh)
        throw Error(
            fmt::format("{}: an overlay file colours the mesh given before it; name the "
                        "surface (lh.pial, a .gii surface, ...) first",
                        file.string()));
      Json& mesh = objects[*last_mesh];
      if (mesh.contains("overlay"))
        throw Error(fmt::format("{}: the mesh '{}' has an overlay already ({}); one per mesh",
                                file.string(), mesh["name"].get<std::string>(),
                                mesh["overlay"]["file"].get<std::string>()));
      mesh["overlay"] = automatic_overlay(absolute);
      continue;
    }
    if (const detail::StreamlineFormat* tracts =
            is_dicom_source(file) ? nullptr
                                  : detail::find_streamline_format(detail::probe_file(file));
        tracts && !tracts->read) {
      // Per-point values (.tsf) of the tractogram given before them.
      if (!last_streamlines)
        throw Error(fmt::format("{}: {} holds values of a tractogram: give it after its .tck",
                                file.string(), file.filename().string()));
      objects[*last_streamlines]["source"]["values"].push_back(absolute.string());
      continue;
    } else if (tracts) {
      last_streamlines = objects.size();
      objects.push_back({{"name", object_name(file, taken)},
                         {"type", "streamlines"},
                         {"source", {{"file", absolute.string()}}}});
      continue;
    }
    if (const detail::ConnectomeFormat* connectome =
            is_dicom_source(file) ? nullptr
                                  : detail::find_connectome_format(detail::probe_file(file))) {
      if (!connectome->read) {  // a BrainNet .edge: the edges of the .node given before it
        if (last_nodes >= objects.size()) throw Error(needs_message(file, identify_file(file)));
        objects[last_nodes]["source"]["edges"] = absolute.string();
        last_nodes = SIZE_MAX;
        continue;
      }
      if (file.extension() == ".node") last_nodes = objects.size();
      objects.push_back({{"name", object_name(file, taken)},
                         {"type", "connectome"},
                         {"source", {{"file", absolute.string()}}}});
      continue;
    }
    if (std::optional<Json> channels = channel_objects(file, absolute, taken)) {
      for (Json& object : *channels) objects.push_back(std::move(object));
      continue;
    }
    Json object = {{"name", object_name(file, taken)}};
    if (is_dicom_source(file) || is_volume_file(file)) {
      object["type"] = "volume";
      object["source"] = {{"file", absolute.string()}};
    } else if (is_mesh_file(file)) {
      last_mesh = objects.size();
      object["type"] = "mesh";
      object["source"] = {{"file", absolute.string()}};
      object["material"] = {
          {"color", color_json(mesh_palette()[meshes++ % mesh_palette().size()])}};
    } else {
      // Not a volume or mesh: a file of another kind that needs something beside it, or none.
      throw Error(needs_message(file, identify_file(file)));
    }
    objects.push_back(std::move(object));
  }
  if (coarse_levels)
    for (Json& o : objects)
      if (o["type"] == "volume" && detail::is_zarr_folder(o["source"]["file"].get<std::string>()))
        o["source"]["level"] = "view";
  Json document = {{"camera", {{"view", view}}},
                   {"image", {{"width", 512}, {"height", 512}}},
                   {"objects", std::move(objects)}};
  for (const std::string& assignment : overrides)
    scene_json::apply_override(document, assignment, kOrigin);
  SceneDocument read(std::move(document), kOrigin, ".", {}, {}, region);
  mark_label_maps(read);
  read.write_out_choices();  // the framed camera, each automatic transfer function
  return read;
}

}  // namespace imx
