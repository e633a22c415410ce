// 3D Slicer's segmentation fields (.seg.nrrd): SegmentN_Name, _Color, _LabelValue, _Layer.
#include <algorithm>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include <fmt/format.h>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "labels/colour_table_readers.hpp"
#include "labels/label_text.hpp"

namespace imx::labels_detail {
namespace {

// The most segments a file may declare (Slicer's own segmentations hold tens to hundreds).
constexpr int64_t kMaxSegments = 1 << 16;

struct SegmentFields {
  std::optional<std::string> name, color, label_value, layer;
  int line = 0;  // where the segment was first named
};

// NRRD key/value escapes: "\n" is a newline, "\\" a backslash.
std::string unescape(std::string_view v) {
  std::string out;
  for (size_t i = 0; i < v.size(); ++i) {
    if (v[i] == '\\' && i + 1 < v.size() && (v[i + 1] == 'n' || v[i + 1] == '\\')) {
      out += v[i + 1] == 'n' ? '\n' : '\\';
      ++i;
    } else {
      out += v[i];
    }
  }
  return out;
}

int64_t whole_number(const std::string& text, const std::string& field, const std::string& what) {
  int64_t v = 0;
  const auto t = tokens(text);
  if (t.size() != 1 || !parse_int(t[0], v))
    throw Error(fmt::format("{}: field '{}' = '{}' is not an integer", what, field, text));
  return v;
}

}  // namespace

std::vector<NrrdKeyValue> nrrd_key_values(std::string_view header, const std::string& what) {
  std::vector<NrrdKeyValue> out;
  std::unordered_set<std::string_view> keys;  // duplicates found in linear time
  const std::vector<std::string_view> rows = lines(header);
  keys.reserve(rows.size());
  for (size_t n = 1; n < rows.size(); ++n) {  // line 1 is the magic
    if (rows[n].empty()) break;               // the end of an attached header
    const size_t sep = rows[n].find(":=");
    if (rows[n].front() == '#' || sep == std::string_view::npos) continue;
    const std::string_view key = rows[n].substr(0, sep);  // a view into `header`
    if (!keys.insert(key).second)
      throw Error(fmt::format("{}: line {}: field '{}' is given twice", what, n + 1, key));
    out.push_back({std::string(key), unescape(rows[n].substr(sep + 2)), static_cast<int>(n + 1)});
  }
  return out;
}

std::vector<LabelEntry> parse_slicer_segments(const std::vector<NrrdKeyValue>& fields, int layers,
                                              int layer, const std::string& what) {
  // By number: segments are numbered from 0 without gaps (checked below), so a vector serves.
  std::vector<SegmentFields> segments;
  for (const NrrdKeyValue& kv : fields) {
    if (kv.key.rfind("Segment", 0) != 0 || kv.key.rfind("Segmentation", 0) == 0) continue;
    const size_t underscore = kv.key.find('_');
    int64_t n = 0;
    if (underscore == std::string::npos ||
        !parse_int(std::string_view(kv.key).substr(7, underscore - 7), n) || n < 0 ||
        n >= kMaxSegments)
      throw Error(fmt::format("{}: line {}: field '{}' is not SegmentN_<property> with N in 0-{}",
                              what, kv.line, kv.key, kMaxSegments - 1));
    if (static_cast<size_t>(n) >= segments.size()) segments.resize(static_cast<size_t>(n) + 1);
    SegmentFields& s = segments[static_cast<size_t>(n)];
    if (s.line == 0) s.line = kv.line;
    const std::string_view property = std::string_view(kv.key).substr(underscore + 1);
    if (property == "Name") s.name = kv.value;
    if (property == "Color") s.color = kv.value;
    if (property == "LabelValue") s.label_value = kv.value;
    if (property == "Layer") s.layer = kv.value;
  }
  if (segments.empty())
    throw Error(what + ": no SegmentN_ fields; not a 3D Slicer segmentation (.seg.nrrd)");
  // Files before Slicer 4.11 keep one segment per layer, as label 1: no LabelValue, no Layer.
  const bool legacy = !segments.front().label_value && !segments.front().layer;
  std::vector<int> per_layer(static_cast<size_t>(layers), 0);
  std::vector<LabelEntry> out;
  std::unordered_map<int32_t, size_t> by_value;  // the layer's labels, checked in linear time
  for (size_t n = 0; n < segments.size(); ++n) {
    const SegmentFields& s = segments[n];
    const std::string seg = fmt::format("Segment{}", n);
    if (s.line == 0) {  // a gap: the next segment named is past it (the last one always is)
      size_t next = n + 1;
      while (segments[next].line == 0) ++next;
      throw Error(
          fmt::format("{}: Segment{} has fields but Segment{} has none: the segments must "
                      "be numbered from 0 without gaps",
                      what, next, n));
    }
    if (!s.name) throw Error(fmt::format("{}: {}_Name is missing", what, seg));
    if (legacy != (!s.label_value && !s.layer) || !s.label_value != !s.layer)
      throw Error(
          fmt::format("{}: {} {} _LabelValue and _Layer while Segment0 {}; the segment "
                      "fields disagree",
                      what, seg, s.label_value && s.layer ? "has" : "lacks",
                      legacy ? "lacks them" : "has them"));
    const int64_t value = legacy ? 1 : whole_number(*s.label_value, seg + "_LabelValue", what);
    const int64_t in_layer = legacy ? n : whole_number(*s.layer, seg + "_Layer", what);
    if (in_layer < 0 || in_layer >= layers)
      throw Error(fmt::format("{}: {}_Layer is {}, but the file has {} layer{} (0-{})", what, seg,
                              in_layer, layers, layers == 1 ? "" : "s", layers - 1));
    if (value <= 0 || value > kMaxLabelMagnitude)
      throw Error(fmt::format("{}: {}_LabelValue is {}; a segment's label is 1-{} (0 is empty)",
                              what, seg, value, kMaxLabelMagnitude));
    ++per_layer[static_cast<size_t>(in_layer)];
    if (in_layer != layer) continue;
    LabelEntry e;
    e.value = static_cast<int32_t>(value);
    e.name = *s.name;
    if (s.color) {
      const auto t = tokens(*s.color);
      double c[3];
      if (t.size() != 3 || !parse_double(t[0], c[0]) || !parse_double(t[1], c[1]) ||
          !parse_double(t[2], c[2]) || std::min({c[0], c[1], c[2]}) < 0.0 ||
          std::max({c[0], c[1], c[2]}) > 1.0)
        throw Error(
            fmt::format("{}: {}_Color = '{}' is not three numbers in [0, 1]", what, seg, *s.color));
      e.color = display_to_linear(glm::vec3(c[0], c[1], c[2]));  // as Slicer shows it
    } else {
      e.color = default_label_color(e.value);  // Slicer generates one too
    }
    if (auto [it, fresh] = by_value.try_emplace(e.value, out.size()); !fresh)
      throw Error(fmt::format("{}: {} and '{}' both have label {} in layer {}", what, seg,
                              out[it->second].name, e.value, layer));
    out.push_back(std::move(e));
  }
  for (int k = 0; k < layers; ++k)
    if (per_layer[static_cast<size_t>(k)] == 0)
      throw Error(
          fmt::format("{}: layer {} of {} has no segment; the segment fields disagree "
                      "with the layers",
                      what, k, layers));
  return out;
}

}  // namespace imx::labels_detail
