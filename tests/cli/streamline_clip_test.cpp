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

#include "core/colour.hpp"
#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "streamline_bundle.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

// The plane the tests cut with (LPS): kept where dot(p - point, normal) >= 0. The file's RAS x
// is LPS -x, so the plane cuts the values' range where RAS x = -point.x.
const glm::dvec3 kPoint(-5.0, 0.0, 0.0);
const glm::dvec3 kNormal = glm::normalize(glm::dvec3(1.0, 0.4, 0.0));

nlohmann::json bundle(const test::TempDir& dir, bool clipped, const nlohmann::json& look = {}) {
  nlohmann::json o = test::bundle_object(dir);
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

TEST(StreamlineClip, NoTubeShowsOnTheRemovedSideOfThePlane) {
  test::TempDir dir;
  test::write_bundle(dir);
  for (const char* method : {"zslab-hybrid", "mdvr", "peel", "reference"}) {
    // Each method's own uncut tubes: zslab-hybrid covers silhouettes, the others do not.
    const Image whole = render_scene(test::kFromAbove, 100, bundle(dir, false), method);
    const Image cut = render_scene(test::kFromAbove, 100, bundle(dir, true), method);
    size_t removed = 0, kept = 0, kept_shown = 0, removed_shown = 0;
    for (int y = 0; y < 100; ++y)
      for (int x = 0; x < 100; ++x) {
        // The plane is vertical: a pixel's whole ray lies on one side, at this distance.
        const double side = glm::dot(test::world_from_above(x, y) - kPoint, kNormal);
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
  test::write_bundle(dir);
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
  const float cap_grey = (5.0f + test::kBundleLength) / (2.0f * test::kBundleLength);
  for (const char* method : {"zslab-hybrid", "mdvr", "reference"}) {
    const Image image = render_scene(from_cut, 80, o, method);
    // 2 pixels per mm; the view's right is LPS -y, up +z: a tube at LPS (y, z) is at pixel
    // (40 - 2y, 40 - 2z): the file's rows at RAS y (LPS -y) at 40 + 2 RAS y.
    for (float ry : test::kBundleRowsY)
      for (float z : test::kBundleRowsZ) {
        const int px = static_cast<int>(40 + 2 * ry), py = static_cast<int>(40 - 2 * z);
        const glm::vec4 c = image.at(px, py);
        EXPECT_GT(c.a, 0.99f) << method << " " << ry << " " << z;
        // The map's grey is a display grey (docs/colour.md): compared as the PNG shows it.
        EXPECT_NEAR(srgb_encode(c.r), cap_grey, 0.02f) << method << " " << ry << " " << z;
      }
    // Between the tubes: the plane draws nothing.
    EXPECT_LT(image.at(40, 40).a, 0.01f) << method;
  }
}

TEST(StreamlineClip, TheMethodsDrawTheSameCut) {
  test::TempDir dir;
  test::write_bundle(dir);
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
