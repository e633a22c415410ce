// Parser for a volume's "transfer_function": RGBA points, a named Slicer preset, a preset file
// (Slicer .vp, ParaView colour-map JSON) or a colour map over a range with a threshold, optionally
// shifted and scaled along the value axis.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/colour.hpp"
#include "core/edit_distance.hpp"
#include "intermix/error.hpp"
#include "presets/colormap.hpp"
#include "presets/colormap_tf.hpp"
#include "presets/paraview_colormap.hpp"
#include "presets/tf_adjust.hpp"
#include "presets/volume_presets.hpp"
#include "presets/vp_file.hpp"
#include "scene/scene_parsers.hpp"

namespace imx::scene_json {
namespace {

TransferFunction parse_points(const JsonReader& points) {
  TransferFunction tf;
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
    point.rgba = display_to_linear(point.rgba);  // display colours; opacity as given
    tf.points.push_back(point);
  }
  return tf;
}

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// {"colormap": name, "range": [lo, hi], "threshold", "symmetric", "opacity"}
// (presets/colormap_tf.hpp says what each means).
TransferFunction parse_colormap_form(const JsonReader& r) {
  ColormapTransferFunction c;
  c.map = parse_colormap(r.get("colormap"));
  const JsonReader range = r.get("range");
  const glm::dvec2 lo_hi = range.vec2();
  c.lo = lo_hi.x;
  c.hi = lo_hi.y;
  if (!(c.lo < c.hi))
    range.fail(fmt::format("[{}, {}]: the first value must be below the second", c.lo, c.hi));
  if (auto v = r.find("symmetric")) c.symmetric = v->boolean();
  if (c.symmetric && c.lo < 0.0)
    range.fail(
        fmt::format("[{}, {}]: with \"symmetric\" the range is of magnitudes |value|, so "
                    "it starts at 0 or above",
                    c.lo, c.hi));
  if (auto v = r.find("threshold")) {
    c.threshold = v->number(c.symmetric ? Range::non_negative() : Range::any());
    if (*c.threshold > c.hi)
      v->fail(
          fmt::format("{} is above the range's end {}: nothing would show", *c.threshold, c.hi));
  }
  if (auto v = r.find("opacity"))
    c.opacity = static_cast<float>(v->number(Range::closed(0.0, 1.0)));
  try {
    return colormap_transfer_function(c);
  } catch (const Error& e) {
    r.fail(e.what());
  }
}

}  // namespace

Colormap parse_colormap(const JsonReader& v) {
  const std::string name = v.string();
  if (std::optional<Colormap> map = find_colormap(name)) return *map;
  const std::vector<std::string> names(kColormapNames.begin(), kColormapNames.end());
  v.fail(fmt::format("{} is not a colour map{}; they are: {}", v.text(), did_you_mean(name, names),
                     fmt::join(names, ", ")));
}

ParsedTransferFunction parse_transfer_function(const JsonReader& r, SceneContext& context) {
  r.check_keys({"points", "preset", "file", "colormap", "name", "range", "threshold", "symmetric",
                "opacity", "shift", "scale", "unit_distance"});
  const int sources =
      int{r.has("points")} + int{r.has("preset")} + int{r.has("file")} + int{r.has("colormap")};
  if (sources != 1)
    r.fail(sources == 0 ? "missing required key 'points' (or a \"preset\" name, a preset "
                          "\"file\" or a \"colormap\" with a \"range\")"
                        : "give one of \"points\", \"preset\", \"file\" and \"colormap\", not "
                          "several");
  if (!r.has("colormap"))
    for (const char* key : {"range", "threshold", "symmetric", "opacity"})
      if (r.has(key)) r.get(key).fail("applies only with a \"colormap\"");
  ParsedTransferFunction out;
  double centre = 0.0;  // what "scale" stretches about
  JsonReader source = r;
  if (auto map = r.find("colormap")) {
    source = *map;
    out.transfer_function = parse_colormap_form(r);
    centre = 0.5 * (out.transfer_function.points.front().value +
                    out.transfer_function.points.back().value);
  } else if (auto points = r.find("points")) {
    source = *points;
    out.transfer_function = parse_points(*points);
    centre = 0.5 * (out.transfer_function.points.front().value +
                    out.transfer_function.points.back().value);
  } else if (auto preset = r.find("preset")) {
    source = *preset;
    const std::string name = preset->string();
    std::optional<SlicerVolumeProperty> p = find_volume_preset(name);
    if (!p) {
      const std::vector<std::string> names = volume_preset_names();
      preset->fail(fmt::format("{} is not a volume-rendering preset{}; they are: {}",
                               preset->text(), did_you_mean(name, names), fmt::join(names, ", ")));
    }
    out.transfer_function = to_transfer_function(*p);
    out.shading = to_shading(*p);
    centre = adjust_centre(*p);
    if (!gradient_opacity_is_trivial(*p))
      context.notes.push_back(
          fmt::format("{}: preset '{}' has a gradient opacity, which intermix does not apply",
                      preset->path(), name));
  } else {
    source = r.get("file");
    const std::filesystem::path path = context.resolve_file(source);
    const std::string ext = lower_extension(path);
    if (ext != ".vp" && ext != ".json")
      source.fail(fmt::format(
          "'{}' is neither a 3D Slicer volume property (.vp) nor a ParaView colour map (.json)",
          path.string()));
    if (ext != ".json" && r.has("name"))
      r.get("name").fail("only a ParaView colour-map file (.json) holds several maps to name");
    try {
      if (ext == ".vp") {
        SlicerVolumeProperty p = read_vp_file(path);
        out.transfer_function = to_transfer_function(p);
        out.shading = to_shading(p);
        centre = adjust_centre(p);
        if (!gradient_opacity_is_trivial(p))
          context.notes.push_back(fmt::format(
              "{}: has a gradient opacity, which intermix does not apply", path.string()));
      } else {
        std::string name;
        if (auto n = r.find("name")) name = n->string();
        ParaviewColormap map = read_paraview_colormap(path, name);
        out.transfer_function = std::move(map.transfer_function);
        centre = 0.5 * (out.transfer_function.points.front().value +
                        out.transfer_function.points.back().value);
        for (std::string& note : map.notes) context.notes.push_back(std::move(note));
      }
    } catch (const FileError& e) {
      source.fail_file(e.what(), e.code());
    } catch (const Error& e) {
      source.fail(e.what());  // the reader's message names the file and field; add the JSON path
    }
  }
  if (r.has("name") && !r.has("file"))
    r.get("name").fail("only a ParaView colour-map \"file\" has a \"name\"");

  double shift = 0.0, scale = 1.0;
  if (auto v = r.find("shift")) shift = v->number();
  if (auto v = r.find("scale")) scale = v->number(Range::open_closed(0.0, 1e6));
  if (shift != 0.0 || scale != 1.0) shift_and_scale(out.transfer_function, centre, shift, scale);

  TransferFunction& tf = out.transfer_function;
  // The table is indexed in float: the whole span must be a finite float too.
  if (!std::isfinite(static_cast<float>(tf.points.back().value) -
                     static_cast<float>(tf.points.front().value)))
    source.fail(fmt::format("the values span [{}, {}], wider than a float can hold",
                            tf.points.front().value, tf.points.back().value));
  if (auto v = r.find("unit_distance")) tf.unit_distance = v->number(Range::length());
  return out;
}

}  // namespace imx::scene_json
