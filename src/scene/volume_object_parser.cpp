// Parser for a "volume" object: its source, placement, style, transfer function and clipping.
#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <new>
#include <system_error>
#include <tuple>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/edit_distance.hpp"
#include "intermix/dicom.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "io/voxels/raw_voxels.hpp"
#include "io/zarr/ome_zarr_reader.hpp"
#include "scene/automatic_look.hpp"
#include "scene/channel_blend.hpp"
#include "scene/channel_look.hpp"
#include "scene/label_map_parser.hpp"
#include "scene/look_sample.hpp"
#include "scene/scene_parsers.hpp"
#include "scene/world_space.hpp"
#include "volume/compact_voxels.hpp"

namespace imx::scene_json {
namespace {

constexpr int kDefaultPhantomSize = 128;

// Loads (or reuses) the volume a "source" names; errors from the readers get the JSON path.
// A DICOM source (folder, DICOMDIR, DICM file) also gives its series' window.
// With context.region, only the box it chooses for `object` is read: `placed` gets where.
// What a source says of itself beyond its voxels (DICOM series only).
struct SourceFacts {
  std::optional<glm::dvec2> window;
  std::string modality, units;
  // With context.region: the voxels an automatic look is chosen from (look_sample.hpp).
  std::function<VolumeData()> look_sample;
  std::optional<detail::OmeChannel> channel;  // an OME-Zarr channel's colour and window
};

// What a file source's header says before its voxels are read (it is cheap next to them): the
// grid can be held whole (else VolumeTooLarge: the caller may render it in bricks), and how many
// frames there are, noted when the source names none.
void check_header(const VolumeHeader& h, const std::filesystem::path& path, const std::string& key,
                  bool named, SceneContext& context) {
  detail::require_holdable(h, path.string());
  context.frame_counts[key] = h.frames;
  if (!named && h.frames > 1)
    context.notes.push_back(
        fmt::format("{}: frame 0 of {} (name another with \"source\": {{\"frame\": K}})",
                    path.string(), h.frames));
}

// Whole-number float voxels (CT resampled to float32) held as int16 or uint16: the same values at
// half the bytes per sample. The copy's peak holds the float and the integer voxels at once, 1.5
// times the floats: up to 768 MiB of floats that stays within the big-data rule (docs/big_data.md:
// resident memory at most 1.25 times the voxels' bytes plus 200 MB), and within the budget.
constexpr uint64_t kMostCompactedBytes = uint64_t{768} << 20;

void hold_compactly(VolumeData& volume, const std::string& what, std::vector<std::string>& notes) {
  if (volume.type() != VoxelType::f32) return;
  const uint64_t bytes = volume.voxel_count() * sizeof(float);
  if (bytes > kMostCompactedBytes || bytes + bytes / 2 > input_limits().max_memory) return;
  std::optional<VoxelStorage> compact = compact_integer_voxels(volume);
  if (!compact) return;
  volume.voxels = std::move(*compact);
  notes.push_back(
      fmt::format("{}: its float32 voxels are whole numbers: held as {} (the same "
                  "values, half the memory)",
                  what, volume.type() == VoxelType::i16 ? "int16" : "uint16"));
}

// The longest edge (mm) of a voxel of a grid placed by `m`, and the longest extent of its box.
double longest_edge(const glm::dmat4& m) {
  return std::max({glm::length(glm::dvec3(m[0])), glm::length(glm::dvec3(m[1])),
                   glm::length(glm::dvec3(m[2]))});
}
double longest_extent(const VolumeHeader& h) {
  double extent = 0.0;
  for (int a = 0; a < 3; ++a)
    extent = std::max(extent, glm::length(glm::dvec3(h.index_to_world[a])) * h.dims[a]);
  return extent;
}

// An OME-Zarr source's resolution level: "level" K (0, the default: full resolution); "auto":
// the finest level one process can hold whole (require_holdable), with a note; or "view" (what
// the viewer opens): that, or the coarsest level whose voxel still fits a pixel of the image's
// rows across the image's longest extent when it is coarser (finer levels follow in bricks).
int zarr_level(const JsonReader& src, const std::filesystem::path& path, bool blended,
               SceneContext& context) {
  const std::optional<JsonReader> asked = src.find("level");
  if (!asked) return 0;
  const int levels =
      asked->reading(path.string(), [&] { return detail::read_ome_zarr_level_count(path); });
  if (!asked->json().is_string()) {
    const int level = asked->integer(0, 1 << 10);
    if (level >= levels)
      asked->fail(fmt::format("level {} requested: {} has {} (0 to {})", level,
                              path.filename().string(), levels, levels - 1));
    return level;
  }
  const bool for_view = asked->choice({"auto", "view"}) == "view";
  const auto header = [&](int level) {
    return asked->reading(path.string(), [&] { return detail::read_ome_zarr_header(path, level); });
  };
  const double pixel = longest_extent(header(0)) / std::max(context.image_rows, 1);
  for (int level = 0; level < levels; ++level) {
    VolumeHeader h = header(level);
    if (blended) h.type = VoxelType::u8;
    try {
      detail::require_holdable(h, path.string());
    } catch (const VolumeTooLarge&) {
      continue;
    }
    std::string why = "the finest that fits in memory";
    if (for_view)
      for (int coarser = level + 1;
           coarser < levels && longest_edge(header(coarser).index_to_world) <= pixel; ++coarser) {
        level = coarser;
        h = header(level);
        why =
            fmt::format("the coarsest whose voxel fits a pixel of the {} rows", context.image_rows);
      }
    if (level > 0)
      context.notes.push_back(
          fmt::format("{}: level {} of {} ({}x{}x{}), {}; intermix render "
                      "renders level 0 in bricks",
                      path.string(), level, levels, h.dims.x, h.dims.y, h.dims.z, why));
    return level;
  }
  asked->fail_too_large(
      fmt::format("no level of {} fits in memory ({} levels)", path.filename().string(), levels));
}

std::shared_ptr<const VolumeData> load_volume_source(const JsonReader& src, SceneContext& context,
                                                     SourceFacts& facts, const std::string& object,
                                                     VolumeObject& placed) {
  if (!context.given_meshes.empty() && src.json().is_object() && src.has("$mesh"))
    src.fail("is a mesh the program gave, not a volume");
  if (!context.given_volumes.empty() && src.json().is_object() && src.has("$volume")) {
    src.check_keys({"$volume"});
    JsonReader id = src.get("$volume");
    auto it = context.given_volumes.find(id.string());
    if (it == context.given_volumes.end()) id.fail(id.text() + " is not a volume of this scene");
    return it->second;
  }
  src.check_keys({"phantom", "size", "file", "series", "units", "slice_spacing_mm", "frame",
                  "channel", "channels", "level"});
  const bool phantom = src.has("phantom"), file = src.has("file");
  if (phantom == file)
    src.fail(phantom ? "give either \"phantom\" or \"file\", not both"
                     : "needs \"phantom\" (a built-in volume) or \"file\"");
  std::string key, what;
  std::function<VolumeData()> load;
  std::function<VolumeHeader()> header;                 // for context.region
  std::function<VolumeData(const VoxelBox&)> load_box;  // for context.region
  JsonReader culprit = src;
  auto refuse_dicom_keys = [&] {
    for (const char* dicom_only : {"series", "units", "slice_spacing_mm"})
      if (auto v = src.find(dicom_only))
        v->fail(fmt::format("only DICOM sources (a folder, DICOMDIR or .dcm file) take \"{}\"",
                            dicom_only));
  };
  std::optional<int> frame;  // of a multi-frame (4-D) file or series
  if (auto v = src.find("frame")) {
    if (phantom) v->fail("phantoms have one frame");
    frame = v->integer(0, 1 << 20);
  }
  std::optional<int> channel;  // of a multi-channel OME-Zarr image
  std::optional<JsonReader> channel_reader = src.find("channel");
  if (channel_reader) {
    if (phantom) channel_reader->fail("phantoms have one channel");
    channel = channel_reader->integer(0, 1 << 20);
  }
  std::optional<ChannelBlend> blend;  // all of its channels blended into one colour volume
  std::optional<JsonReader> blend_reader = src.find("channels");
  if (blend_reader) {
    if (phantom) blend_reader->fail("phantoms have one channel");
    if (channel_reader)
      blend_reader->fail("give \"channel\" (one) or \"channels\" (blended), not both");
    blend = blend_reader->choice({"add", "max"}) == "add" ? ChannelBlend::add : ChannelBlend::max;
  }
  if (phantom) {
    refuse_dicom_keys();
    if (auto v = src.find("level")) v->fail("phantoms have one resolution level");
    JsonReader name_reader = src.get("phantom");
    std::string name = name_reader.string();
    std::vector<std::string> names = phantom_names();
    if (std::find(names.begin(), names.end(), name) == names.end())
      name_reader.fail(fmt::format("{} is not a built-in phantom{}; they are: {}",
                                   name_reader.text(), did_you_mean(name, names),
                                   fmt::join(names, ", ")));
    int size = kDefaultPhantomSize;
    if (auto v = src.find("size")) size = v->integer(8, 1024);
    key = fmt::format("phantom:{}:{}", name, size);
    what = fmt::format("phantom '{}' of size {}", name, size);
    load = [name, size, what] {
      detail::require_holdable(phantom_header(name, size), what);
      return make_phantom(name, size);
    };
    header = [name, size] { return phantom_header(name, size); };
    load_box = [name, size](const VoxelBox& box) { return make_phantom_region(name, size, box); };
  } else {
    if (auto v = src.find("size")) v->fail("only phantoms have a size");
    culprit = src.get("file");
    if (culprit.string().empty()) culprit.fail("the file name is empty");
    std::filesystem::path path(culprit.string());
    if (path.is_relative() && !context.base_dir.empty()) path = context.base_dir / path;
    std::error_code ec;
    if (!std::filesystem::is_directory(path, ec))  // a DICOM folder is a valid "file" too
      path = context.resolve_file(culprit);
    std::filesystem::path canonical = std::filesystem::weakly_canonical(path, ec);
    key = "file:" + (ec ? path : canonical).string();
    what = path.string();
    if (!detail::is_zarr_folder(path))
      if (auto v = src.find("level"))
        v->fail("only OME-Zarr images (a .zarr folder) have resolution levels");
    if (is_dicom_source(path)) {
      for (const auto& r : {channel_reader, blend_reader})
        if (r) r->fail("only OME-Zarr images (a .zarr folder) have channels");
      DicomReadOptions options;
      if (auto v = src.find("series")) {
        options.series = v->json().is_number_integer() ? std::to_string(v->json().get<long long>())
                                                       : v->string();
        key += ":series=" + options.series;
      }
      if (auto v = src.find("units")) {
        options.units = v->choice({"suv"});
        key += ":units=suv";
      }
      if (auto v = src.find("slice_spacing_mm")) {
        options.slice_spacing_mm = v->number(Range::length());
        key += fmt::format(":spacing={}", *options.slice_spacing_mm);
      }
      if (frame) {
        options.frame = *frame;
        key += fmt::format(":frame={}", *frame);
      }
      load = [path, options, key, &context] {
        DicomVolume d = read_dicom(path, options);
        context.frame_counts[key] = d.frames;
        for (const std::string& note : d.notes)
          context.notes.push_back(fmt::format("{}: {}", path.string(), note));
        if (d.window) context.windows[key] = *d.window;
        context.modalities[key] = {d.series.modality, d.units};
        return std::move(d.volume);
      };
    } else if (detail::is_zarr_folder(path)) {
      refuse_dicom_keys();
      const std::vector<detail::OmeChannel> channels =
          culprit.reading(what, [&] { return detail::read_ome_zarr_channels(path); });
      const int count = static_cast<int>(channels.size());
      if (channel && *channel >= count)
        channel_reader->fail(fmt::format("channel {} requested: {} has {} (0 to {})", *channel,
                                         path.filename().string(), count, count - 1));
      const int c = channel.value_or(0), k = frame.value_or(0);
      const int level = zarr_level(src, path, blend.has_value(), context);
      if (level > 0) key += fmt::format(":level={}", level);
      // A channel the file describes (or one of several) is drawn in its own colour and window.
      if (!blend && (channel || count > 1 || channels[0].listed)) facts.channel = channels[c];
      key += blend ? fmt::format(":channels={}:frame={}", blend_reader->string(), k)
                   : fmt::format(":channel={}:frame={}", c, k);
      // One channel, or (blended) the active ones, every one when none is.
      const auto read = [path, level, k, c, blend, channels]() -> VolumeData {
        if (!blend) return detail::read_ome_zarr(path, level, k, c);
        std::vector<VolumeData> grids;
        std::vector<detail::OmeChannel> looks;
        const bool any = std::any_of(channels.begin(), channels.end(),
                                     [](const detail::OmeChannel& o) { return o.active; });
        for (size_t n = 0; n < channels.size(); ++n)
          if (channels[n].active || !any) {
            grids.push_back(detail::read_ome_zarr(path, level, k, static_cast<int>(n)));
            looks.push_back(channels[n]);
          }
        return blend_channels(grids, looks, *blend, path.string());
      };
      header = [path, level, blend] {
        VolumeHeader h = detail::read_ome_zarr_header(path, level);
        if (blend) h.type = VoxelType::u8;  // the blend's scalar
        return h;
      };
      load = [path, read, header, key, named = frame.has_value(), &context] {
        check_header(header(), path, key, named, context);
        return read();
      };
      load_box = [path, read, level, k, c, blend](const VoxelBox& box) {
        return blend ? crop(read(), box, path.string())
                     : detail::read_ome_zarr_region(path, box, level, k, c);
      };
    } else {
      for (const auto& r : {channel_reader, blend_reader})
        if (r)
          r->fail(
              "only OME-Zarr images (a .zarr folder) have channels: give \"frame\" for a 4-D "
              "file");
      refuse_dicom_keys();
      const int k = frame.value_or(0);
      if (frame) key += fmt::format(":frame={}", k);
      load = [path, k, key, named = frame.has_value(), &context] {
        check_header(read_volume_header(path), path, key, named, context);
        return read_volume(path, k);
      };
      header = [path] { return read_volume_header(path); };
      load_box = [path, k](const VoxelBox& box) { return read_volume_region(path, box, k); };
    }
  }
  auto window_of = [&] {
    if (auto it = context.windows.find(key); it != context.windows.end()) facts.window = it->second;
    if (auto it = context.modalities.find(key); it != context.modalities.end())
      std::tie(facts.modality, facts.units) = it->second;
  };
  VoxelBox box;
  if (context.region)
    culprit.reading(what, [&] {
      // DICOM has no header-only read: the series is read once and cropped.
      if (!header) {
        auto whole = std::make_shared<VolumeData>(load());
        header = [whole] {
          return VolumeHeader{whole->dims, whole->type(), whole->index_to_world, 1, {}};
        };
        load_box = [whole, what](const VoxelBox& b) { return crop(*whole, b, what); };
      }
      VolumeHeader h = header();
      facts.look_sample = [h, load_box] { return look_sample(h, load_box); };
      box = context.region(object, h);
      placed.source_dims = h.dims;
      if (box != VoxelBox::whole(h.dims)) {
        key += fmt::format(":box={},{},{}-{},{},{}", box.lo.x, box.lo.y, box.lo.z, box.hi.x,
                           box.hi.y, box.hi.z);
        load = [load_box, box] { return load_box(box); };
      }
    });
  context.used.insert(key);
  auto frames_of = [&] {
    placed.frame = frame.value_or(0);
    if (auto it = context.frame_counts.find(key); it != context.frame_counts.end())
      placed.frames = it->second;
  };
  if (auto it = context.volumes.find(key); it != context.volumes.end()) {
    frames_of();
    window_of();
    if (context.region) placed.region = box;
    return it->second;
  }
  auto data = culprit.reading(what, [&] {
    VolumeData volume = load();
    volume.validate(what);
    if (const size_t missing = non_finite_count(volume); missing > 0)
      context.notes.push_back(fmt::format("{}: {} of {} voxels are NaN or infinite: no data", what,
                                          missing, volume.voxel_count()));
    hold_compactly(volume, what, context.notes);
    return std::make_shared<const VolumeData>(std::move(volume));
  });
  context.volumes.emplace(key, data);
  frames_of();
  window_of();
  if (context.region) placed.region = box;
  return data;
}

}  // namespace

std::vector<ClipPlane> parse_clip_planes(const JsonReader& r, MeshSpace space) {
  std::vector<ClipPlane> planes;
  for (const JsonReader& e : r.elements()) {
    e.check_keys({"point", "normal"});
    ClipPlane plane;
    plane.point = to_lps(e.get("point").vec3(Range::coordinate()), space);
    plane.normal = to_lps(e.get("normal").direction(), space);
    planes.push_back(plane);
  }
  return planes;
}

VolumeObject parse_volume_object(const JsonReader& r, SceneContext& context) {
  r.check_keys({"name", "type", "source", "transform", "style", "iso_value", "xray_mode",
                "transfer_function", "shading", "clip_planes", "clip", "visible", "labels",
                "interpolation", "units", "window", "slabs"});
  VolumeObject v;
  v.name = r.get("name").string();
  glm::dmat4 transform(1.0);
  std::optional<std::filesystem::path> field;  // a displacement field warps the data instead
  if (auto t = r.find("transform"))
    if (field = displacement_field_of(*t, context); !field)
      transform = parse_transform(*t, context);
  // Style "labels" is dvr through a label map (label_map_parser.hpp): the TF is not used.
  const bool labels = r.has("style") && r.get("style").json() == "labels";
  if (labels) {
    if (auto tf = r.find("transfer_function"))
      tf->fail("style 'labels' draws the colour table (\"labels\"), not a transfer function");
    v.transfer_function.points = {TfPoint{0.0, glm::vec4(1.0f)}};
  } else {
    for (const char* key : {"labels", "interpolation"})
      if (auto k = r.find(key)) k->fail(fmt::format("\"{}\" applies only to style 'labels'", key));
  }
  if (auto s = r.find("style"); s && !labels) {
    std::string style = s->choice({"dvr", "iso", "mip", "minip", "xray", "labels"});
    v.style = style == "dvr"     ? VolumeStyle::dvr
              : style == "iso"   ? VolumeStyle::iso
              : style == "mip"   ? VolumeStyle::mip
              : style == "minip" ? VolumeStyle::minip
                                 : VolumeStyle::xray;
  }
  if (auto m = r.find("xray_mode")) {
    if (v.style != VolumeStyle::xray) m->fail("xray_mode applies only to style 'xray'");
    v.xray_mode =
        m->choice({"integral", "average"}) == "average" ? XrayMode::average : XrayMode::integral;
  }
  if (auto iso = r.find("iso_value"))
    v.iso_value = iso->number();
  else if (v.style == VolumeStyle::iso)
    r.fail("missing required key 'iso_value' (the style is iso)");
  std::optional<Shading> preset_shading;  // a preset's own, when the volume gives none
  const bool automatic = !r.has("transfer_function") && v.style != VolumeStyle::iso && !labels;
  if (auto tf = r.find("transfer_function")) {
    ParsedTransferFunction parsed = parse_transfer_function(*tf, context);
    v.transfer_function = std::move(parsed.transfer_function);
    preset_shading = parsed.shading;
  } else if (v.style == VolumeStyle::iso) {
    v.transfer_function.points = {TfPoint{v.iso_value, glm::vec4(1.0f)}};  // white, opaque
  }
  if (auto s = r.find("shading")) v.shading = parse_shading(*s);
  if (auto c = r.find("clip_planes")) v.clip_planes = parse_clip_planes(*c, context.world_space);
  // "clip" names meshes, which come later in the file: parse_clip_meshes reads it.
  // The source last: reading a large file is the slowest step, so cheap errors come first.
  SourceFacts facts;
  v.data = load_volume_source(r.get("source"), context, facts, v.name, v);
  if (field) v.data = warped_volume(r.get("transform").get("file"), v.data, *field, context);
  v.display_window = facts.window;
  if (facts.channel && facts.channel->window) v.display_window = facts.channel->window;
  v.units = facts.units;
  if (auto w = r.find("window")) v.window = parse_window(*w);  // the 2-D views' window
  if (auto s = r.find("slabs")) v.reading_slabs = parse_reading_slabs(*s);
  if (auto u = r.find("units")) {  // a label for colour bars and readouts ("t", "z", "%")
    v.units = u->string();
    if (v.units.size() > 16) u->fail("a units label has at most 16 characters");
  }
  if (automatic) {
    // Chosen from the voxels, and parsed as the file would spell it (automatic_look.hpp); read
    // by region, from slices of the whole, the same for every region.
    std::optional<VolumeData> sample;
    if (context.region) sample = r.get("source").reading(v.name, facts.look_sample);
    const VolumeData& looked = sample ? *sample : *v.data;
    const AutomaticLook look = facts.channel ? channel_look(*facts.channel, looked)
                                             : automatic_look(looked, facts.modality, facts.units);
    const JsonReader tf(look.transfer_function, r.origin(), r.path() + ".transfer_function");
    ParsedTransferFunction parsed = parse_transfer_function(tf, context);
    v.transfer_function = std::move(parsed.transfer_function);
    preset_shading =
        look.shading.is_null()
            ? parsed.shading
            : parse_shading(JsonReader(look.shading, r.origin(), r.path() + ".shading"));
    context.notes.push_back(
        fmt::format("{} ('{}'): no transfer_function: {}", r.path(), v.name, look.reason));
    context.automatic_looks[r.path()] = {look.transfer_function, look.shading};
  }
  if (!r.has("shading") && preset_shading) v.shading = *preset_shading;
  if (labels) {
    r.get("source").reading(v.name,
                            [&] { check_label_voxels(*v.data, "volume '" + v.name + "'"); });
    v.labels = parse_label_map(r, context, v.frame, parse_visible(r));
  }
  // Hidden: every alpha 0, so it adds nothing anywhere, while planes still sample its data.
  if (!parse_visible(r))
    for (TfPoint& p : v.transfer_function.points) p.rgba.a = 0.0f;
  if (!context.region) {  // the whole source
    v.source_dims = v.data->dims;
    v.region = VoxelBox::whole(v.data->dims);
  }
  v.index_to_world = transform * v.data->index_to_world;
  return v;
}

}  // namespace imx::scene_json
