// Parser for a label volume's colour table and classification.
#include "scene/label_map_parser.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx::scene_json {
namespace {

constexpr double kMaxLabel = 16777216.0;  // 2^24

std::vector<LabelEntry> parse_inline_table(const JsonReader& table) {
  std::vector<LabelEntry> entries;
  for (const JsonReader& e : table.elements()) {
    e.check_keys({"value", "name", "color", "opacity", "visible"});
    LabelEntry entry;
    const double value = e.get("value").number(Range::closed(-kMaxLabel, kMaxLabel));
    if (value != std::floor(value)) e.get("value").fail("a label is an integer");
    entry.value = static_cast<int32_t>(value);
    entry.name = e.has("name") ? e.get("name").string() : fmt::format("label {}", entry.value);
    entry.color = e.has("color") ? e.get("color").color() : default_label_color(entry.value);
    if (auto o = e.find("opacity"))
      entry.opacity = static_cast<float>(o->number(Range::closed(0, 1)));
    if (auto v = e.find("visible")) entry.visible = v->boolean();
    entries.push_back(std::move(entry));
  }
  return entries;
}

// The entry a label has before overrides: its row, else the palette's colour (hidden for
// background, or when a table was given and does not list it).
LabelEntry base_entry(const LabelMap& map, int32_t value) {
  for (const LabelEntry& e : map.entries)
    if (e.value == value) return e;
  LabelEntry e;
  e.value = value;
  e.name = fmt::format("label {}", value);
  e.color = value == 0 ? glm::vec3(0.0f) : default_label_color(value);
  e.visible = map.palette_unlisted && value != 0;
  return e;
}

// "overrides": [{"value", "visible", "opacity", "color"}, ...] change rows of the table (or add
// rows to the palette): what the viewer's label edits write.
void apply_overrides(const JsonReader& list, LabelMap& map) {
  for (const JsonReader& o : list.elements()) {
    o.check_keys({"value", "visible", "opacity", "color"});
    const double value = o.get("value").number(Range::closed(-kMaxLabel, kMaxLabel));
    if (value != std::floor(value)) o.get("value").fail("a label is an integer");
    LabelEntry e = base_entry(map, static_cast<int32_t>(value));
    if (auto v = o.find("visible")) e.visible = v->boolean();
    if (auto v = o.find("opacity")) e.opacity = static_cast<float>(v->number(Range::closed(0, 1)));
    if (auto v = o.find("color")) e.color = v->color();
    auto it = std::find_if(map.entries.begin(), map.entries.end(),
                           [&](const LabelEntry& x) { return x.value == e.value; });
    if (it != map.entries.end())
      *it = std::move(e);
    else
      map.entries.push_back(std::move(e));
  }
}

}  // namespace

LabelEntry label_entry(const LabelMap& map, int32_t value) {
  return base_entry(map, value);
}

std::shared_ptr<const LabelMap> parse_label_map(const JsonReader& r, SceneContext& context,
                                                int layer, bool visible) {
  auto map = std::make_shared<LabelMap>();
  if (auto i = r.find("interpolation"))
    map->interpolation = i->choice({"smooth", "nearest"}) == "nearest" ? LabelInterpolation::nearest
                                                                       : LabelInterpolation::smooth;
  if (auto l = r.find("labels")) {
    l->check_keys({"file", "table", "unit_distance", "overrides"});
    if (l->has("file") && l->has("table"))
      l->fail("give either \"file\" (a colour table) or \"table\" (a list of labels), not both");
    if (!l->has("file") && !l->has("table") && !l->has("overrides"))
      l->fail("give \"file\" (a colour table) or \"table\" (a list of labels)");
    if (auto u = l->find("unit_distance")) map->unit_distance = u->number(Range::length());
    if (auto f = l->find("file")) {
      const std::filesystem::path path = context.resolve_file(*f);
      const std::string ext = path.extension().string();
      const bool nrrd = ext == ".nrrd" || ext == ".nhdr";
      map->entries =
          f->reading(path.string(), [&] { return read_label_table(path, nrrd ? layer : 0); });
      map->source = path.string();
    } else if (l->has("table")) {
      const JsonReader table = l->get("table");
      map->entries = parse_inline_table(table);
      table.reading("inline table", [&] { validate_label_entries(map->entries, table.path()); });
      map->source = "inline";
    }
    if (l->has("file") || l->has("table"))
      map->palette_unlisted = false;  // a table names what shows
    else
      map->source = "palette";
    if (auto o = l->find("overrides")) apply_overrides(*o, *map);
  }
  map->shown = visible;
  return map;
}

void check_label_voxels(const VolumeData& data, const std::string& what) {
  if (data.type() != VoxelType::f32) return;  // u8, i16 and u16 hold integers
  const auto& voxels = std::get<VoxelBuffer<float>>(data.voxels);
  const float* v = voxels.data();
  for (size_t i = 0; i < voxels.size(); ++i)
    if (!(std::abs(v[i]) <= kMaxLabel) || v[i] != std::floor(v[i]))
      throw Error(fmt::format("{}: style 'labels' needs integer voxels, but voxel {} is {}", what,
                              i, v[i]));
}

}  // namespace imx::scene_json
