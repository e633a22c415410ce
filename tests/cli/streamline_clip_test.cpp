// Clip planes on a streamlines object, rendered: no tube shows on the removed side of the plane
// (the plane projected into the image), the cut is capped in the tubes' colour at the plane, and
// the methods that take surfaces draw the same cut.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "mrtrix_tracks.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

constexpr float kLength = 30.0f;  // the streamlines run along x from -30 to 30 mm
const std::vector<float> kRowsY = {-12.0f, -4.0f, 4.0f, 12.0f};
const std::vector<float> kRowsZ = {-6.0f, -2.0f, 2.0f, 6.0f};

// A bundle of 16 straight streamlines along x (RAS in the file, so LPS x and y are negated:
// the file's y rows are LPS -y), a point every mm, each point valued by its RAS x.
void write_bundle(const std::filesystem::path& tck, const std::filesystem::path& tsf) {
  std::vector<std::vector<float>> points, values;
  for (float y : kRowsY)
    for (float z : kRowsZ) {
      points.emplace_back();
      values.emplace_back();
      for (float x = -kLength; x <= kLength; x += 1.0f) {
        points.back().insert(points.back().end(), {x, -y, z});
        values.back().push_back(x);
      }
    }
  test::write_mrtrix_tracks(tck, "mrtrix tracks", points, 3);
  test::write_mrtrix_tracks(tsf, "mrtrix track scalars", values, 1);
}

// The plane the tests cut with (LPS): kept where dot(p - point, normal) >= 0. The file's RAS x
// is LPS -x, so the plane cuts the values' range where RAS x = -point.x.
const glm::dvec3 kPoint(-5.0, 0.0, 0.0);
const glm::dvec3 kNormal = glm::normalize(glm::dvec3(1.0, 0.4, 0.0));

nlohmann::json bundle(const test::TempDir& dir, bool clipped, const nlohmann::json& look = {}) {
  nlohmann::json o = {
      {"name", "bundle"},
      {"type", "streamlines"},
      {"radius", 1.5},
      {"color_by", "point_value"},
      {"value", "bundle"},
      {"colormap", "grey"},
      {"range", {-kLength, kLength}},
      {"shading", {{"enabled", false}}},
      {"source",
       {{"file", (dir / "bundle.tck").string()}, {"values", {(dir / "bundle.tsf").string()}}}}};
  if (clipped)
    o["clip_planes"] = {
        {{"point", {kPoint.x, kPoint.y, kPoint.z}}, {"normal", {kNormal.x, kNormal.y, kNormal.z}}}};
  if (look.is_object()) o.update(look);
  return o;
}

// `coverage`: render.tube_coverage (auto: on in the zSlab methods only).
Image render_scene(const nlohmann::json& camera, int size, const nlohmann::json& object,
                   const char* method, const char* coverage = "auto") {
  const nlohmann::json scene = {
      {"camera", camera},
      {"image", {{"width", size}, {"height", size}, {"background", {0, 0, 0, 0}}}},
      {"render", {{"method", method}, {"spp", 1}, {"tube_coverage", coverage}}},
      {"objects", {object}}};
  return render(parse_scene(scene.dump(), ".", "test"));
}

// From above (LPS +z), orthographic, 1 pixel per mm: image column x shows world x = 50 - x - 0.5
// (the view's right is LPS -x), row y shows world y = y + 0.5 - 50 (up is -y).
const nlohmann::json kFromAbove = {{"eye", {0, 0, 300}},
                                   {"target", {0, 0, 0}},
                                   {"up", {0, -1, 0}},
                                   {"projection", "orthographic"},
                                   {"ortho_height", 100}};
glm::dvec3 world_from_above(int x, int y) {
  return {50.0 - x - 0.5, y + 0.5 - 50.0, 0.0};
}

TEST(StreamlineClip, NoTubeShowsOnTheRemovedSideOfThePlane) {
  test::TempDir dir;
  write_bundle(dir / "bundle.tck", dir / "bundle.tsf");
  for (const char* method : {"zslab-hybrid", "mdvr", "peel", "reference"}) {
    // Each method's own uncut tubes: zslab-hybrid covers silhouettes, the others do not.
    const Image whole = render_scene(kFromAbove, 100, bundle(dir, false), method);
    const Image cut = render_scene(kFromAbove, 100, bundle(dir, true), method);
    size_t removed = 0, kept = 0, kept_shown = 0, removed_shown = 0;
    for (int y = 0; y < 100; ++y)
      for (int x = 0; x < 100; ++x) {
        // The plane is vertical: a pixel's whole ray lies on one side, at this distance.
        const double side = glm::dot(world_from_above(x, y) - kPoint, kNormal);
        if (whole.at(x, y).a < 0.9f) continue;  // tubes cover this pixel when nothing is cut
        if (side < -1.0) {
          ++removed;
          removed_shown += cut.at(x, y).a > 0.01f;
        } else if (side > 1.0) {
          ++kept;
          kept_shown += cut.at(x, y).a > 0.9f;
        }
      }
    ASSERT_GT(removed, 200u) << method;  // the geometry is what the test thinks it is
    ASSERT_GT(kept, 200u) << method;
    EXPECT_EQ(removed_shown, 0u) << method << ": tube pixels on the removed side";
    EXPECT_EQ(kept_shown, kept) << method << ": kept tube pixels missing";
  }
}

TEST(StreamlineClip, LookingAtTheCutFaceShowsTheCapInTheTubesColourThere) {
  test::TempDir dir;
  write_bundle(dir / "bundle.tck", dir / "bundle.tsf");
  // A plane across x (kept: LPS x >= -5, RAS x <= 5), seen along its normal from the removed
  // side: each tube shows a disc, its colour the value at the plane (RAS x = 5). Without caps
  // the rays would see the inside of the tubes' far ends (RAS x = -30, black).
  const nlohmann::json from_cut = {{"eye", {-300, 0, 0}},
                                   {"target", {0, 0, 0}},
                                   {"up", {0, 0, 1}},
                                   {"projection", "orthographic"},
                                   {"ortho_height", 40}};
  nlohmann::json o = bundle(dir, false);
  o["clip_planes"] = {{{"point", {-5, 0, 0}}, {"normal", {1, 0, 0}}}};
  const float cap_grey = (5.0f + kLength) / (2.0f * kLength);
  for (const char* method : {"zslab-hybrid", "mdvr", "reference"}) {
    const Image image = render_scene(from_cut, 80, o, method);
    // 2 pixels per mm; the view's right is LPS -y, up +z: a tube at LPS (y, z) is at pixel
    // (40 - 2y, 40 - 2z): the file's rows at RAS y (LPS -y) at 40 + 2 RAS y.
    for (float ry : kRowsY)
      for (float z : kRowsZ) {
        const int px = static_cast<int>(40 + 2 * ry), py = static_cast<int>(40 - 2 * z);
        const glm::vec4 c = image.at(px, py);
        EXPECT_GT(c.a, 0.99f) << method << " " << ry << " " << z;
        EXPECT_NEAR(c.r, cap_grey, 0.02f) << method << " " << ry << " " << z;
      }
    // Between the tubes: the plane draws nothing.
    EXPECT_LT(image.at(40, 40).a, 0.01f) << method;
  }
}

TEST(StreamlineClip, TheMethodsDrawTheSameCut) {
  test::TempDir dir;
  write_bundle(dir / "bundle.tck", dir / "bundle.tsf");
  const nlohmann::json oblique = {
      {"eye", {-120, -90, 70}}, {"target", {0, 0, 0}}, {"up", {0, 0, 1}}, {"fov_deg", 30}};
  // The same rays in every method: silhouette coverage off everywhere, then on everywhere.
  for (const char* coverage : {"off", "on"})
    for (double opacity : {1.0, 0.5}) {
      const nlohmann::json look = {{"opacity", opacity}, {"shading", {{"enabled", true}}}};
      const Image reference =
          render_scene(oblique, 96, bundle(dir, true, look), "reference", coverage);
      const Image whole =
          render_scene(oblique, 96, bundle(dir, false, look), "reference", coverage);
      const double unclipped = psnr(reference, whole);
      EXPECT_LT(unclipped, 25.0) << "the cut changes the picture";
      for (const char* method : {"zslab-hybrid", "mdvr", "peel"}) {
        const double db =
            psnr(render_scene(oblique, 96, bundle(dir, true, look), method, coverage), reference);
        EXPECT_GT(db, 40.0) << method << " opacity " << opacity << " coverage " << coverage
                            << " (unclipped " << unclipped << " dB)";
      }
    }
}

}  // namespace
}  // namespace imx
