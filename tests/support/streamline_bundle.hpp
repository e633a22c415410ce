// The rendered streamline tests' shared scene: a bundle of 16 straight streamlines written as
// MRtrix .tck with .tsf values, its scene object, and an orthographic view from above at one
// pixel per mm, so that a pixel's position and grey say where a tube lies.
#pragma once
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "mrtrix_tracks.hpp"
#include "temp_dir.hpp"

namespace imx::test {

inline constexpr float kBundleLength = 30.0f;  // the streamlines run along x from -30 to 30 mm
inline const std::vector<float> kBundleRowsY = {-12.0f, -4.0f, 4.0f, 12.0f};
inline const std::vector<float> kBundleRowsZ = {-6.0f, -2.0f, 2.0f, 6.0f};

// dir/bundle.tck and dir/bundle.tsf: 16 straight streamlines along x (RAS in the file, so LPS
// x and y are negated: the file's y rows are LPS -y), a point every mm, each valued by its RAS x.
inline void write_bundle(const TempDir& dir) {
  std::vector<std::vector<float>> points, values;
  for (float y : kBundleRowsY)
    for (float z : kBundleRowsZ) {
      points.emplace_back();
      values.emplace_back();
      for (float x = -kBundleLength; x <= kBundleLength; x += 1.0f) {
        points.back().insert(points.back().end(), {x, -y, z});
        values.back().push_back(x);
      }
    }
  write_mrtrix_tracks(dir / "bundle.tck", "mrtrix tracks", points, 3);
  write_mrtrix_tracks(dir / "bundle.tsf", "mrtrix track scalars", values, 1);
}

// The bundle as a scene object: tubes of radius 1.5 mm, unlit, grey by the values.
inline nlohmann::json bundle_object(const TempDir& dir) {
  return {{"name", "bundle"},
          {"type", "streamlines"},
          {"radius", 1.5},
          {"color_by", "point_value"},
          {"value", "bundle"},
          {"colormap", "grey"},
          {"range", {-kBundleLength, kBundleLength}},
          {"shading", {{"enabled", false}}},
          {"source",
           {{"file", (dir / "bundle.tck").string()}, {"values", {(dir / "bundle.tsf").string()}}}}};
}

// From above (LPS +z), orthographic, 1 pixel per mm on a 100-pixel image: column x shows world
// x = 50 - x - 0.5 (the view's right is LPS -x), row y shows world y = y + 0.5 - 50 (up is -y).
inline const nlohmann::json kFromAbove = {{"eye", {0, 0, 300}},
                                          {"target", {0, 0, 0}},
                                          {"up", {0, -1, 0}},
                                          {"projection", "orthographic"},
                                          {"ortho_height", 100}};
inline glm::dvec3 world_from_above(int x, int y) {
  return {50.0 - x - 0.5, y + 0.5 - 50.0, 0.0};
}

}  // namespace imx::test
