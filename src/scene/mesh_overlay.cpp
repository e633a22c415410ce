#include "scene/mesh_overlay.hpp"

#include <cmath>
#include <map>
#include <optional>
#include <system_error>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "io/overlay/cifti.hpp"
#include "io/overlay/vertex_overlay.hpp"
#include "io/overlay/volume_overlay.hpp"
#include "scene/surface_sampling.hpp"
#include "volume/tf_lut.hpp"

namespace imx::scene_json {
namespace {

// The deleter of a shared MeshFile: std::get_deleter finds it from any pointer sharing the
// owner, the aliasing pointer to its mesh included.
struct MeshFileDeleter {
  const MeshFile* file = nullptr;
  void operator()(const MeshFile* p) const { delete p; }
};

// How values become colours.
struct ValueColoring {
  TransferFunction transfer_function;
  std::optional<double> threshold;  // with a transfer function of points
  bool symmetric = false;
  bool labels = false;
  std::map<int64_t, glm::vec4> table;  // labels: linear RGB and opacity by key
};

// The keys of a colour-map transfer function, which "overlay" and "color_by" take directly.
constexpr const char* kColormapKeys[] = {"colormap", "range", "threshold", "symmetric", "opacity"};

// "transfer_function", or a colour map given by its keys (a transfer function's colour-map form,
// src/scene/transfer_function_parser.cpp), else `fallback`; "threshold" and "symmetric" beside
// a transfer function hide values below the threshold (|value| with symmetric).
ValueColoring parse_value_coloring(const JsonReader& r, SceneContext& context,
                                   const TransferFunction* fallback) {
  ValueColoring c;
  if (auto tf = r.find("transfer_function")) {
    if (r.has("colormap")) r.fail("give \"transfer_function\" or \"colormap\", not both");
    for (const char* key : {"range", "opacity"})
      if (auto v = r.find(key)) v->fail(fmt::format("\"{}\" belongs to a \"colormap\"", key));
    c.transfer_function = parse_transfer_function(*tf, context).transfer_function;
    if (auto v = r.find("symmetric")) c.symmetric = v->boolean();
    if (auto v = r.find("threshold"))
      c.threshold = v->number(c.symmetric ? Range::non_negative() : Range::any());
    return c;
  }
  if (r.has("colormap")) {
    nlohmann::json form = nlohmann::json::object();
    for (const char* key : kColormapKeys)
      if (r.json().contains(key)) form[key] = r.json()[key];
    const JsonReader tf(form, r.origin(), r.path());
    c.transfer_function = parse_transfer_function(tf, context).transfer_function;
    return c;
  }
  for (const char* key : kColormapKeys)
    if (auto v = r.find(key))
      v->fail(fmt::format("\"{}\" needs a \"colormap\" or a \"transfer_function\"", key));
  if (!fallback) r.fail("needs a \"transfer_function\" or a \"colormap\" for its values");
  c.transfer_function = *fallback;
  return c;
}

// The colour of a vertex whose value is `v` and whose colour without values is `base`: the
// transfer function's where its opacity is above 0 (and the value passes the threshold), the
// label's where the label is in the table and not transparent; `base` elsewhere (no value).
glm::vec3 value_colour(double v, const ValueColoring& c, glm::vec3 base) {
  if (std::isnan(v)) return base;
  if (c.labels) {
    auto it = c.table.find(static_cast<int64_t>(v));
    return it != c.table.end() && it->second.a > 0.0f ? glm::vec3(it->second) : base;
  }
  if (c.threshold && (c.symmetric ? std::abs(v) : v) < *c.threshold) return base;
  const glm::vec4 rgba = evaluate_transfer_function(c.transfer_function, v);
  return rgba.a > 0.0f ? glm::vec3(rgba) : base;
}

Mesh coloured(const Mesh& mesh, const std::vector<double>& values, const ValueColoring& c) {
  Mesh out = mesh;
  out.colors.resize(mesh.positions.size(), glm::vec3(1.0f));
  for (size_t i = 0; i < out.colors.size(); ++i)
    out.colors[i] = value_colour(values[i], c, out.colors[i]);
  return out;
}

std::string pointer_key(const void* p) {
  return fmt::format("{}", p);
}

// The overlay file's values for the surface: a CIFTI-2 file's map of the surface's structure
// ("structure", else the one the surface file says it is), a FreeSurfer per-vertex volume's
// frame, or another overlay file's values (`index`: a GIfTI data array).
detail::VertexOverlay read_overlay_file(const JsonReader& overlay,
                                        const std::filesystem::path& path,
                                        const std::filesystem::path& surface_file,
                                        size_t file_vertices) {
  const JsonReader file_reader = overlay.get("file");
  const bool cifti = detail::is_cifti(path);
  const bool volume = !cifti && !detail::is_overlay_file(path) && is_volume_file(path);
  int index = -1;
  if (auto v = overlay.find("index")) {
    if (cifti || volume)
      v->fail("\"index\" picks a data array of a GIfTI file; \"frame\" picks a map of this one");
    index = v->integer(0, 1 << 20);
  }
  int frame = 0;
  if (auto v = overlay.find("frame")) {
    if (!cifti && !volume)
      v->fail("\"frame\" picks a map of a CIFTI-2 file or a frame of a NIfTI or MGH overlay");
    frame = v->integer(0, static_cast<int>(detail::kMaxCiftiMaps));
  }
  std::optional<std::string> structure;
  if (auto v = overlay.find("structure")) {
    if (!cifti) v->fail("\"structure\" picks a surface structure of a CIFTI-2 file");
    structure = v->string();
  }
  return file_reader.reading(path.string(), [&] {
    if (cifti) {
      const detail::CiftiFile c = detail::read_cifti(path);
      const std::string chosen =
          structure ? *structure
                    : detail::cifti_structure_of_surface(c, surface_file, file_vertices);
      return detail::cifti_overlay(c, chosen, frame, path.string());
    }
    if (volume)
      return detail::volume_as_overlay(read_volume(path, frame), file_vertices, path.string());
    return detail::read_vertex_overlay(path, index);
  });
}

}  // namespace

std::shared_ptr<const Mesh> share_mesh_file(MeshFile file) {
  auto* raw = new MeshFile(std::move(file));
  std::shared_ptr<const MeshFile> owner(raw, MeshFileDeleter{raw});
  return std::shared_ptr<const Mesh>(owner, &raw->mesh);
}

const MeshFile* mesh_file_of(const std::shared_ptr<const Mesh>& mesh) {
  const MeshFileDeleter* d = std::get_deleter<MeshFileDeleter>(mesh);
  return d ? d->file : nullptr;
}

std::shared_ptr<const Mesh> apply_overlay(const JsonReader& overlay,
                                          const std::shared_ptr<const Mesh>& source,
                                          SceneContext& context,
                                          const std::filesystem::path& surface_file) {
  overlay.check_keys({"file", "array", "index", "frame", "structure", "color", "transfer_function",
                      "colormap", "range", "threshold", "symmetric", "opacity"});
  const bool has_file = overlay.has("file"), has_array = overlay.has("array");
  if (has_file == has_array)
    overlay.fail(has_file ? "give \"file\" or \"array\", not both"
                          : "needs \"file\" (an overlay file) or \"array\" (point data of the "
                            "mesh file)");
  const MeshFile* file = mesh_file_of(source);
  std::string key =
      fmt::format("overlay\n{}\n{}", pointer_key(source.get()), overlay.json().dump());
  std::filesystem::path path;
  if (has_file) {
    path = context.resolve_file(overlay.get("file"));
    std::error_code ec;
    key += fmt::format("\n{}", std::filesystem::weakly_canonical(path, ec).string());
  }
  context.used.insert(key);
  if (auto it = context.meshes.find(key); it != context.meshes.end()) return it->second;

  // The values at the file's vertices, and whether they are labels.
  const size_t file_vertices = file ? file->info.file_vertices : source->positions.size();
  std::vector<double> values;
  ValueColoring coloring;
  if (has_file) {
    const JsonReader file_reader = overlay.get("file");
    detail::VertexOverlay read = read_overlay_file(overlay, path, surface_file, file_vertices);
    values = file_reader.reading(
        path.string(), [&] { return detail::overlay_values(read, file_vertices, path.string()); });
    if (read.labels) {
      coloring.labels = true;
      for (const detail::OverlayLabel& l : read.table)
        coloring.table.emplace(l.key, display_to_linear(l.rgba));
      if (auto v = overlay.find("color")) {
        if (read.members.empty()) v->fail("\"color\" applies to a .label file's vertices");
        const glm::vec3 c = v->color();
        coloring.table[1] = glm::vec4(c, 1.0f);
      }
    }
  } else {
    const JsonReader array = overlay.get("array");
    const std::string name = array.string();
    if (auto v = overlay.find("index")) v->fail("\"index\" picks a data array of a GIfTI file");
    for (const char* key : {"frame", "structure"})
      if (auto v = overlay.find(key))
        v->fail(fmt::format("\"{}\" applies to an overlay file", key));
    if (!file) array.fail("the mesh is not read from a file: it has no point data");
    const MeshPointData* found = nullptr;
    std::vector<std::string> names;
    for (const MeshPointData& d : file->point_data) {
      names.push_back(d.name);
      if (d.name == name) found = &d;
    }
    if (!found)
      array.fail(fmt::format("the mesh file has no point data '{}'{}", name,
                             names.empty() ? std::string(" (it has none)")
                                           : fmt::format(" (it has {})", fmt::join(names, ", "))));
    if (found->components != 1)
      array.fail(
          fmt::format("point data '{}' has {} components; an overlay takes one value per "
                      "vertex",
                      name, found->components));
    values = found->values;
  }
  if (auto v = overlay.find("color"); v && !coloring.labels)
    v->fail("\"color\" applies to a .label file's vertices");
  if (coloring.labels) {
    for (const char* k :
         {"transfer_function", "colormap", "range", "threshold", "symmetric", "opacity"})
      if (auto v = overlay.find(k))
        v->fail(
            fmt::format("a label overlay is coloured by its own table: \"{}\" does not apply", k));
  } else {
    coloring = parse_value_coloring(overlay, context, nullptr);
  }
  // Onto the mesh's vertices, which computed normals may have welded and split.
  std::vector<double> at_vertex(source->positions.size());
  for (size_t i = 0; i < at_vertex.size(); ++i) {
    const size_t f = file && i < file->file_vertex.size() ? file->file_vertex[i] : i;
    at_vertex[i] = f < values.size() ? values[f] : std::nan("");
  }
  auto mesh = std::make_shared<const Mesh>(coloured(*source, at_vertex, coloring));
  context.meshes.emplace(key, mesh);
  return mesh;
}

void apply_color_by(const std::vector<JsonReader>& objects, Scene& scene, SceneContext& context,
                    const std::map<std::string, std::string>& types) {
  for (size_t i = 0; i < objects.size() && i < scene.order.size(); ++i) {
    if (scene.order[i].kind != ObjectKind::mesh) continue;
    const std::optional<JsonReader> r = objects[i].find("color_by");
    if (!r) continue;
    if (objects[i].has("overlay"))
      r->fail("give \"overlay\" or \"color_by\", not both: each colours every vertex");
    r->check_keys({"volume", "depth_mm", "reduce", "transfer_function", "colormap", "range",
                   "threshold", "symmetric", "opacity"});
    const JsonReader volume_reader = r->get("volume");
    const int v = find_volume(volume_reader, volume_reader.string(), scene, types);
    const VolumeObject& volume = scene.volumes[static_cast<size_t>(v)];
    if (volume.data->dims != volume.source_dims && volume.source_dims != glm::ivec3(0))
      volume_reader.fail("the volume is loaded by region here; color_by needs all of it");
    SurfaceSampling sampling;
    if (auto d = r->find("depth_mm")) {
      const std::vector<double> depth = d->numbers(2, Range::closed(-100.0, 100.0));
      if (depth[0] > depth[1])
        d->fail(fmt::format("[{}, {}]: the first depth must not be above the second", depth[0],
                            depth[1]));
      sampling.depth_from = depth[0];
      sampling.depth_to = depth[1];
    }
    if (auto m = r->find("reduce")) {
      const std::string reduce = m->choice({"mean", "max", "min"});
      sampling.reduce = reduce == "max"   ? SurfaceReduce::max
                        : reduce == "min" ? SurfaceReduce::min
                                          : SurfaceReduce::mean;
    }
    const ValueColoring coloring = parse_value_coloring(*r, context, &volume.transfer_function);
    MeshObject& object = scene.meshes[static_cast<size_t>(scene.order[i].index)];
    std::string key = fmt::format("color_by\n{}\n{}\n{}\n{}", pointer_key(object.mesh.get()),
                                  pointer_key(volume.data.get()), r->json().dump(), volume.frame);
    for (int c = 0; c < 4; ++c)
      for (int row = 0; row < 4; ++row) key += fmt::format(" {}", volume.index_to_world[c][row]);
    for (const TfPoint& p : coloring.transfer_function.points)
      key += fmt::format(" {} {} {} {} {}", p.value, p.rgba.r, p.rgba.g, p.rgba.b, p.rgba.a);
    context.used.insert(key);
    auto [it, fresh] = context.placed_meshes.try_emplace(key);
    if (fresh) {
      const std::vector<double> values =
          sample_along_normals(*object.mesh, *volume.data, volume.index_to_world, sampling);
      it->second = std::make_shared<const Mesh>(coloured(*object.mesh, values, coloring));
    }
    object.mesh = it->second;
  }
}

}  // namespace imx::scene_json
