// Parsers for thick slabs: a plane's "slab" and a volume's reading views' "slabs".
#include <fmt/format.h>

#include "scene/scene_parsers.hpp"

namespace imx::scene_json {

SlabProjection parse_slab(const JsonReader& r) {
  r.expect_object();
  r.check_keys({"thickness", "mode"});
  SlabProjection s;
  s.thickness = r.get("thickness").number(Range::closed(0.0, kMaxSlabThicknessMm));
  if (auto v = r.find("mode")) {
    const std::string mode = v->choice({"mip", "minip", "mean"});
    s.mode = mode == "mip" ? SlabMode::mip : mode == "minip" ? SlabMode::minip : SlabMode::mean;
  }
  return s;
}

std::array<SlabProjection, 3> parse_reading_slabs(const JsonReader& r) {
  r.expect_object();
  r.check_keys({"axial", "coronal", "sagittal"});
  std::array<SlabProjection, 3> slabs{};
  const char* names[] = {"axial", "coronal", "sagittal"};
  for (size_t k = 0; k < 3; ++k)
    if (auto v = r.find(names[k])) slabs[k] = parse_slab(*v);
  return slabs;
}

nlohmann::json slab_json(const SlabProjection& s) {
  const char* mode = s.mode == SlabMode::mip ? "mip" : s.mode == SlabMode::minip ? "minip" : "mean";
  return {{"thickness", s.thickness}, {"mode", mode}};
}

nlohmann::json reading_slabs_json(const std::array<SlabProjection, 3>& slabs) {
  nlohmann::json out = nlohmann::json::object();
  const char* names[] = {"axial", "coronal", "sagittal"};
  for (size_t k = 0; k < 3; ++k)
    if (slabs[k].thickness > 0.0) out[names[k]] = slab_json(slabs[k]);
  return out;
}

}  // namespace imx::scene_json
