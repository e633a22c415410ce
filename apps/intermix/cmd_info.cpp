// intermix info FILE | --phantom NAME | --presets | --formats | FILE --memory | SCENE
// --annotations: what a volume or mesh holds; the preset names; the format registry; what
// rendering a file holds resident; what a scene's annotations measure.
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "core/math.hpp"
#include "intermix/dicom.hpp"
#include "intermix/error.hpp"
#include "intermix/formats.hpp"
#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "intermix/scene.hpp"
#include "io/streamlines/streamline_formats.hpp"
#include "io/zarr/ome_zarr_reader.hpp"
#include "measure/measurement.hpp"
#include "presets/colormap.hpp"
#include "presets/volume_presets.hpp"
#include "presets/window_presets.hpp"
#include "scene/scene_document.hpp"
#include "scene/scene_from_files.hpp"
#include "intermix/render.hpp"
#include "methods/resident_memory.hpp"

namespace imx::cli {

namespace {

// A volume's grid and placement, from its header (a volume too large to hold: its voxels'
// range is then not read).
nlohmann::json describe_grid(const VolumeHeader& v) {
  const glm::dvec3 s(glm::length(glm::dvec3(v.index_to_world[0])),
                     glm::length(glm::dvec3(v.index_to_world[1])),
                     glm::length(glm::dvec3(v.index_to_world[2])));
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 4; ++r)
    rows.push_back({v.index_to_world[0][r], v.index_to_world[1][r], v.index_to_world[2][r],
                    v.index_to_world[3][r]});
  glm::dvec3 lo_w(INFINITY), hi_w(-INFINITY);
  for (int c = 0; c < 8; ++c) {
    glm::dvec3 idx((c & 1) ? v.dims.x - 1 : 0, (c & 2) ? v.dims.y - 1 : 0,
                   (c & 4) ? v.dims.z - 1 : 0);
    glm::dvec3 w = transform_point(v.index_to_world, idx);
    lo_w = glm::min(lo_w, w);
    hi_w = glm::max(hi_w, w);
  }
  return {{"kind", "volume"},
          {"dims", {v.dims.x, v.dims.y, v.dims.z}},
          {"type", voxel_type_name(v.type)},
          {"spacing_mm", {s.x, s.y, s.z}},
          {"index_to_world", rows},
          {"world_bounds_mm", {{lo_w.x, lo_w.y, lo_w.z}, {hi_w.x, hi_w.y, hi_w.z}}}};
}

nlohmann::json describe(const VolumeData& v) {
  nlohmann::json j = describe_grid({v.dims, v.type(), v.index_to_world, 1, {}});
  auto [lo, hi] = v.range();
  j["range"] = {lo, hi};
  return j;
}

// The frames of a multi-frame source, with their labels; nothing for a single frame.
void add_frames(nlohmann::json& j, int frame, int frames, const std::vector<FrameLabel>& labels) {
  if (frames <= 1) return;
  j["frame"] = frame;
  j["frames"] = frames;
  nlohmann::json list = nlohmann::json::array();
  for (const FrameLabel& l : labels) list.push_back(l.text);
  if (!labels.empty()) j["frame_labels"] = list;
}

// A mesh file as read: bounds in LPS, the space the file was in and who said so.
nlohmann::json describe(const MeshFile& file) {
  const Mesh& m = file.mesh;
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const glm::vec3& p : m.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const char* from = "default (no header names one)";
  if (file.info.space_source == MeshSpaceSource::header) from = "header (SPACE= comment or field)";
  if (file.info.space_source == MeshSpaceSource::format) from = "format (GIfTI is RAS)";
  if (file.info.space_source == MeshSpaceSource::option) from = "option";
  return {{"kind", "mesh"},
          {"vertices", file.info.file_vertices},
          {"shading_vertices", m.positions.size()},
          {"triangles", m.triangles.size()},
          {"space", mesh_space_name(file.info.space)},
          {"space_from", from},
          {"normals", file.info.file_normals ? "file" : "computed (angle-weighted, crease 60 deg)"},
          {"colors", file.info.file_colors},
          {"bounds", {{lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z}}}};
}

// What rendering each volume of `file` holds resident, as `intermix render FILE` would render it
// (scene_from_files: its automatic look, the default render settings).
nlohmann::json resident_memory(const std::string& file) {
  const SceneDocument document = scene_from_files({file});
  const Scene& scene = document.scene();
  const std::vector<std::vector<ResidentPart>> resident =
      resident_parts(scene, resolve_method(scene).name);
  nlohmann::json list = nlohmann::json::array();
  for (size_t k = 0; k < scene.volumes.size(); ++k) {
    const VolumeObject& v = scene.volumes[k];
    nlohmann::json parts = nlohmann::json::array();
    uint64_t total = 0, voxels = 0;
    for (const ResidentPart& part : resident[k]) {
      parts.push_back({{"name", part.name}, {"bytes", part.bytes}});
      total += part.bytes;
      if (part.name == "voxels") voxels = part.bytes;
    }
    list.push_back({{"volume", v.name},
                    {"parts", parts},
                    {"total", total},
                    {"per_voxel_byte", voxels ? static_cast<double>(total) / voxels : 0.0}});
  }
  return list;
}

void print_memory(const nlohmann::json& list) {
  for (const nlohmann::json& v : list) {
    std::printf("%s: %s resident, %.2fx its voxels\n", v["volume"].get<std::string>().c_str(),
                format_bytes(v["total"].get<uint64_t>()).c_str(),
                v["per_voxel_byte"].get<double>());
    for (const nlohmann::json& part : v["parts"]) {
      const std::string name = part["name"];
      const uint64_t bytes = part["bytes"];
      std::printf("  %-22s %s\n", name.c_str(),
                  bytes                 ? format_bytes(bytes).c_str()
                  : name == "gradients" ? "none (on the fly)"
                                        : "none");
    }
  }
}

// The LPS box of points, as [[lo], [hi]] (null for none).
template <class Points>
nlohmann::json bounds_of(const Points& points) {
  if (points.empty()) return nullptr;
  glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-lo);
  for (const glm::vec3& p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return {{lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z}};
}

nlohmann::json describe(const Streamlines& s, const std::vector<std::string>& notes) {
  size_t shortest = s.count() ? SIZE_MAX : 0, longest = 0;
  for (size_t i = 0; i < s.count(); ++i) {
    shortest = std::min(shortest, s.length(i));
    longest = std::max(longest, s.length(i));
  }
  nlohmann::json point_values = nlohmann::json::array(), streamline_values = point_values,
                 groups = point_values;
  for (const StreamlineValues& v : s.point_values) point_values.push_back(v.name);
  for (const StreamlineValues& v : s.streamline_values) streamline_values.push_back(v.name);
  for (const StreamlineGroup& g : s.groups)
    groups.push_back({{"name", g.name}, {"streamlines", g.members.size()}});
  return {{"kind", "streamlines"},
          {"streamlines", s.count()},
          {"points", s.points.size()},
          {"points_per_streamline", {shortest, longest}},
          {"world_bounds_mm", bounds_of(s.points)},
          {"point_values", point_values},
          {"streamline_values", streamline_values},
          {"groups", groups},
          {"notes", notes}};
}

nlohmann::json describe(const Connectome& c, const std::vector<std::string>& notes) {
  std::vector<glm::vec3> positions;
  for (const ConnectomeNode& n : c.nodes) positions.push_back(n.position);
  nlohmann::json weights = nullptr;
  if (!c.edges.empty()) {
    const auto [lo, hi] = std::minmax_element(
        c.edges.begin(), c.edges.end(),
        [](const ConnectomeEdge& a, const ConnectomeEdge& b) { return a.weight < b.weight; });
    weights = {lo->weight, hi->weight};
  }
  return {{"kind", "connectome"},
          {"nodes", c.nodes.size()},
          {"edges", c.edges.size()},
          {"edge_weights", weights},
          {"world_bounds_mm", bounds_of(positions)},
          {"notes", notes}};
}

void print_human(const nlohmann::json& j) {
  for (auto it = j.begin(); it != j.end(); ++it)
    std::printf("%-16s %s\n", it.key().c_str(), it.value().dump().c_str());
}

}  // namespace

// The series of a DICOM folder, DICOMDIR or file; with `series`, that series as a volume.
nlohmann::json describe_dicom(const std::string& source, const std::string& series, int frame) {
  if (!series.empty()) {
    DicomReadOptions options;
    options.series = series;
    options.frame = frame;
    DicomVolume d = read_dicom(source, options);
    nlohmann::json j = describe(d.volume);
    j["series"] = d.series.id;
    j["series_uid"] = d.series.uid;
    j["description"] = d.series.description;
    j["modality"] = d.series.modality;
    j["slices_acquired"] = d.series.slices;
    j["units"] = d.units;
    if (d.window) j["window"] = {d.window->x, d.window->y};
    j["notes"] = d.notes;
    add_frames(j, frame, d.frames, d.frame_labels);
    return j;
  }
  nlohmann::json list = nlohmann::json::array();
  std::vector<std::string> refused;
  for (const DicomSeriesInfo& s : list_dicom_series(source, &refused))
    list.push_back({{"id", s.id},
                    {"number", s.number},
                    {"description", s.description},
                    {"modality", s.modality},
                    {"size", {s.columns, s.rows}},
                    {"slices", s.slices},
                    {"localizer", s.localizer},
                    {"uid", s.uid}});
  return {{"kind", "dicom"}, {"series", list}, {"refused", refused}};
}

void print_dicom_series(const nlohmann::json& j) {
  std::printf("%-8s %-28s %-8s %-10s %7s  %s\n", "series", "description", "modality", "size",
              "slices", "uid");
  for (const nlohmann::json& s : j["series"])
    std::printf("%-8s %-28s %-8s %-10s %7d  %s%s\n", s["id"].get<std::string>().c_str(),
                s["description"].get<std::string>().c_str(),
                s["modality"].get<std::string>().c_str(),
                fmt::format("{}x{}", s["size"][0].get<int>(), s["size"][1].get<int>()).c_str(),
                s["slices"].get<int>(), s["uid"].get<std::string>().c_str(),
                s["localizer"].get<bool>() ? " (localizer)" : "");
  // What convert would refuse: every file that starts as DICOM but cannot be read.
  for (const nlohmann::json& r : j["refused"])
    std::printf("refused: %s\n", r.get<std::string>().c_str());
}

// The format registry's rows: one line each, or (json) one array of objects.
void print_formats(bool json) {
  const std::vector<FileFormat> formats = file_formats();
  if (json) {
    nlohmann::json list = nlohmann::json::array();
    for (const FileFormat& f : formats)
      list.push_back({{"kind", f.kind},
                      {"name", f.name},
                      {"extensions", f.extensions},
                      {"by_content", f.by_content},
                      {"gz_extensions", f.gz_extensions},
                      {"writes", f.writes},
                      {"reference", f.reference},
                      {"needs", f.needs},
                      {"fuzz_target", f.fuzz_target},
                      {"fuzz_seeds", f.fuzz_seeds}});
    std::printf("%s\n", nlohmann::json({{"kind", "formats"}, {"formats", list}}).dump().c_str());
    return;
  }
  for (const FileFormat& f : formats)
    std::printf("%-16s %-48s %s%s%s\n", f.kind.c_str(), f.name.c_str(),
                fmt::format("{}", fmt::join(f.extensions, " ")).c_str(),
                f.by_content ? " (or by content)" : "",
                f.writes.empty() ? "" : fmt::format("; writes {}", f.writes).c_str());
}

// A scene's measurements (docs/viewer.md, "Measurements"): CSV, one JSON object, or a line each.
void print_annotations(const Scene& scene, const std::vector<Annotation>& annotations, bool json,
                       bool csv) {
  if (csv) {
    std::printf("%s", measurements_csv(scene, annotations).c_str());
    return;
  }
  nlohmann::json list = nlohmann::json::array();
  for (const Annotation& a : annotations) {
    const Measurement m = measure(a, scene);
    if (!json)
      std::printf("%zu %-8s %s\n", static_cast<size_t>(list.size()), annotation_kind_name(a.kind),
                  measurement_text(a, m).c_str());
    list.push_back(measurement_json(a, m));
  }
  if (json)
    std::printf("%s\n", nlohmann::json({{"kind", "annotations"}, {"annotations", list}})
                            .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)
                            .c_str());
}

Command add_info(CLI::App& app) {
  struct Options {
    std::string file, phantom, series;
    int size = 128;
    int frame = 0;
    bool json = false;
    bool presets = false;
    bool formats = false;
    bool markdown = false;
    bool memory = false;
    bool annotations = false;
    bool csv = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("file", o->file,
                 "a volume (a DICOM folder too) or a mesh; --formats lists every format");
  app.add_option("--phantom", o->phantom, "describe a built-in phantom instead of a file");
  app.add_option("--size", o->size, "phantom size (voxels along the largest axis)");
  app.add_flag("--json", o->json, "print one JSON object on stdout");
  app.add_option("--series", o->series,
                 "DICOM: describe this series (number, id or UID) as a volume, not the list");
  app.add_option("--frame", o->frame, "of a multi-frame (4-D) source: describe this frame")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--formats", o->formats,
               "list every file format intermix reads and writes (the format registry)");
  app.add_flag("--markdown", o->markdown, "with --formats: the README's Markdown table");
  app.add_flag("--memory", o->memory,
               "what rendering FILE holds resident per volume (voxels, gradients, bricks, "
               "tables), as `intermix render FILE` renders it");
  app.add_flag("--annotations", o->annotations,
               "FILE is a scene: what each of its annotations measures (length, angle, ROI area "
               "and statistics), as text, --json or --csv");
  app.add_flag("--csv", o->csv, "with --annotations: one CSV row per annotation");
  app.add_flag("--presets", o->presets,
               "list the transfer-function, window and colour-map names scenes may use");
  return [o]() {
    nlohmann::json j;
    if (o->formats) {
      if (o->markdown) {
        std::printf("%s", file_formats_markdown().c_str());
        return 0;
      }
      print_formats(o->json);
      return 0;
    }
    if (o->csv && !o->annotations) throw Error("info: --csv applies only with --annotations");
    if (o->annotations) {
      if (o->file.empty()) throw Error("info --annotations: give a scene FILE");
      const SceneDocument document = SceneDocument::load(o->file);
      print_annotations(document.scene(), document.annotations(), o->json, o->csv);
      return 0;
    }
    if (o->memory) {
      if (o->file.empty()) throw Error("info --memory: give a FILE (a volume, or a DICOM folder)");
      j = {{"kind", "memory"}, {"file", o->file}, {"volumes", resident_memory(o->file)}};
      if (o->json)
        std::printf("%s\n", j.dump().c_str());
      else
        print_memory(j["volumes"]);
      return 0;
    }
    if (o->presets) {
      j = {{"kind", "presets"},
           {"transfer_function", volume_preset_names()},
           {"window", window_preset_names()},
           {"colormap", std::vector<std::string>(kColormapNames.begin(), kColormapNames.end())}};
    } else if (!o->phantom.empty()) {
      j = describe(make_phantom(o->phantom, o->size));
      j["phantom"] = o->phantom;
    } else if (o->file.empty()) {
      throw Error("info: give a FILE or --phantom NAME");
    } else if (is_dicom_source(o->file)) {
      j = describe_dicom(o->file, o->series, o->frame);
      j["file"] = o->file;
      if (!o->json && o->series.empty()) {
        print_dicom_series(j);
        return 0;
      }
    } else if (const IdentifiedFile identified = identify_file(o->file);
               !identified.needs.empty()) {
      // An overlay, transform or colour table: it says what it needs beside it.
      throw Error(needs_message(o->file, identified));
    } else if (is_volume_file(o->file)) {
      const VolumeHeader header = read_volume_header(o->file);
      try {
        j = describe(read_volume(o->file, o->frame));
      } catch (const VolumeTooLarge&) {
        j = describe_grid(header);
        j["note"] = "too large to hold whole: intermix render renders it in bricks";
      }
      if (detail::is_zarr_folder(o->file)) {
        j["levels"] = detail::read_ome_zarr_level_count(o->file);
        // Each channel as a scene names it ("channel": K) and how OME says to show it.
        nlohmann::json channels = nlohmann::json::array();
        for (const detail::OmeChannel& c : detail::read_ome_zarr_channels(o->file)) {
          nlohmann::json one = {
              {"label", c.label}, {"color", {c.srgb.r, c.srgb.g, c.srgb.b}}, {"active", c.active}};
          if (c.window) one["window"] = {c.window->x, c.window->y};
          channels.push_back(one);
        }
        if (channels.size() > 1) j["channels"] = channels;
      }
      add_frames(j, o->frame, header.frames, header.frame_labels);
      j["file"] = o->file;
    } else if (is_mesh_file(o->file)) {
      j = describe(read_mesh_file(o->file));
      j["file"] = o->file;
    } else if (detail::is_streamline_file(o->file)) {
      std::vector<std::string> notes;
      j = describe(detail::read_streamline_file(o->file, {}, notes), notes);
      j["file"] = o->file;
    } else if (detail::is_connectome_file(o->file)) {
      std::vector<std::string> notes;
      j = describe(detail::read_connectome_file(o->file, notes), notes);
      j["file"] = o->file;
    } else {
      throw Error(unknown_format_message(o->file));  // identify_file has refused it already
    }
    if (o->json)
      std::printf("%s\n", j.dump().c_str());
    else
      print_human(j);
    return 0;
  };
}

}  // namespace imx::cli
