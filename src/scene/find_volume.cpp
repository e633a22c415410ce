#include <fmt/format.h>

#include "core/edit_distance.hpp"
#include "scene/scene_parsers.hpp"

namespace imx::scene_json {

int find_volume(const JsonReader& at, const std::string& name, const Scene& scene,
                const std::map<std::string, std::string>& object_types) {
  for (size_t i = 0; i < scene.volumes.size(); ++i)
    if (scene.volumes[i].name == name) return static_cast<int>(i);
  auto it = object_types.find(name);
  if (it != object_types.end())
    at.fail(fmt::format("'{}' is a {}, not a volume", name, it->second));
  std::vector<std::string> names;
  for (const VolumeObject& v : scene.volumes) names.push_back(v.name);
  at.fail(fmt::format("no volume named '{}'{}", name, did_you_mean(name, names)));
}

}  // namespace imx::scene_json
