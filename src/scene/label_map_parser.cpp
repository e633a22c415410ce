// Parser for a label volume's colour table and classification.
#include "scene/label_map_parser.hpp"

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

}  // namespace

std::shared_ptr<const LabelMap> parse_label_map(const JsonReader& r, SceneContext& context,
                                                int layer, bool visible) {
  auto map = std::make_shared<LabelMap>();
  if (auto i = r.find("interpolation"))
    map->interpolation = i->choice({"smooth", "nearest"}) == "nearest" ? LabelInterpolation::nearest
                                                                       : LabelInterpolation::smooth;
  if (auto l = r.find("labels")) {
    l->check_keys({"file", "table", "unit_distance"});
    if (l->has("file") == l->has("table"))
      l->fail("give either \"file\" (a colour table) or \"table\" (a list of labels), not both");
    if (auto u = l->find("unit_distance")) map->unit_distance = u->number(Range::length());
    if (auto f = l->find("file")) {
      const std::filesystem::path path = context.resolve_file(*f);
      const std::string ext = path.extension().string();
      const bool nrrd = ext == ".nrrd" || ext == ".nhdr";
      map->entries =
          f->reading(path.string(), [&] { return read_label_table(path, nrrd ? layer : 0); });
      map->source = path.string();
    } else {
      const JsonReader table = l->get("table");
      map->entries = parse_inline_table(table);
      table.reading("inline table", [&] { validate_label_entries(map->entries, table.path()); });
      map->source = "inline";
    }
    map->palette_unlisted = false;  // a table names what shows
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
