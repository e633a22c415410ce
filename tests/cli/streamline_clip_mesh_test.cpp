// Clip meshes ("clip") on a streamlines object, rendered: tubes show only inside a ball
// (probing) or only outside it (cutting) at the pixels the ball's projection says, the cut is
// capped in the tubes' colour where the ball's surface crosses them, and the methods that take
// surfaces draw the same cut.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "core/colour.hpp"
#include "expect_error.hpp"
#include "intermix/error.hpp"
#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "streamline_bundle.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

constexpr float kBall = 10.0f;  // the clip ball's radius, centred at the origin

// keep: "inside", "outside", or "" for no clip mesh.
nlohmann::json bundle(const test::TempDir& dir, const std::string& keep,
                      const nlohmann::json& look = {}) {
  nlohmann::json o = test::bundle_object(dir);
  if (!keep.empty()) o["clip"] = {{{"mesh", "ball"}, {"keep", keep}}};
  if (look.is_object()) o.update(look);
  return o;
}

// The ball, not drawn: it only clips.
const nlohmann::json kBallObject = {
    {"name", "ball"},
    {"type", "mesh"},
    {"source", {{"primitive", "sphere"}, {"radius", kBall}, {"segments", 128}}},
    {"material", {{"opacity", 0}}}};

// A faint fog filling a ball of radius 44.8 mm around the bundle, for tubes mixed with a volume.
const nlohmann::json kFog = {
    {"name", "fog"},
    {"type", "volume"},
    {"source", {{"phantom", "sphere"}, {"size", 64}}},
    {"transfer_function",
     {{"points", {{-1, 0.6, 0.7, 1, 0}, {0, 0.6, 0.7, 1, 0.004}, {50, 0.6, 0.7, 1, 0.004}}},
      {"unit_distance", 1}}}};

Image render_scene(const nlohmann::json& camera, int size, const nlohmann::json& object,
                   const char* method, bool fog = false) {
  nlohmann::json scene = {
      {"camera", camera},
      {"image", {{"width", size}, {"height", size}, {"background", {0, 0, 0, 0}}}},
      // The same rays in every method: silhouette coverage (zslab's default) off.
      {"render", {{"method", method}, {"spp", 1}, {"tube_coverage", "off"}}},
      {"objects", {object, kBallObject}}};
  if (fog) scene["objects"].push_back(kFog);
  return render(parse_scene(scene.dump(), ".", "test"));
}

TEST(StreamlineClipMesh, TubesShowOnlyOnTheSideTheBallKeeps) {
  test::TempDir dir;
  test::write_bundle(dir);
  const Image whole = render_scene(test::kFromAbove, 100, bundle(dir, ""), "mdvr");
  for (const char* keep : {"inside", "outside"})
    for (const char* method : {"zslab-hybrid", "mdvr", "peel", "reference"}) {
      const Image cut = render_scene(test::kFromAbove, 100, bundle(dir, keep), method);
      // A vertical ray at distance rho from the ball's axis: under 6 mm every tube it crosses
      // (|z| <= 7.5) lies inside the ball; beyond 10.5 mm none does.
      size_t near = 0, near_wrong = 0, far = 0, far_wrong = 0;
      const bool probing = std::string(keep) == "inside";
      for (int y = 0; y < 100; ++y)
        for (int x = 0; x < 100; ++x) {
          if (whole.at(x, y).a < 0.9f) continue;  // no tube here when nothing is cut
          const double rho = std::hypot(50.0 - x - 0.5, y + 0.5 - 50.0);
          const bool shown = cut.at(x, y).a > 0.9f, empty = cut.at(x, y).a < 0.01f;
          if (rho < 6.0) {
            ++near;
            near_wrong += probing ? !shown : !empty;
          } else if (rho > 10.5) {
            ++far;
            far_wrong += probing ? !empty : !shown;
          }
        }
      ASSERT_GT(near, 30u) << keep << " " << method;  // the geometry is what the test thinks
      ASSERT_GT(far, 300u) << keep << " " << method;
      EXPECT_EQ(near_wrong, 0u) << keep << " " << method << ": pixels within 6 mm of the axis";
      EXPECT_EQ(far_wrong, 0u) << keep << " " << method << ": pixels beyond 10.5 mm";
    }
}

TEST(StreamlineClipMesh, TheCutIsCappedOnTheBallInTheTubesColourThere) {
  test::TempDir dir;
  test::write_bundle(dir);
  // Looking along +x (LPS) at the bundle: the ball keeps each tube of the rows |y| = 4 from
  // LPS x = -sqrt(100 - y^2 - z^2) on, where its cap shows the value there (RAS x = +sqrt(..)).
  // The rows |y| = 12 lie outside the ball and show nothing.
  const nlohmann::json from_side = {{"eye", {-300, 0, 0}},
                                    {"target", {0, 0, 0}},
                                    {"up", {0, 0, 1}},
                                    {"projection", "orthographic"},
                                    {"ortho_height", 40}};
  const Image whole = render_scene(from_side, 80, bundle(dir, ""), "mdvr");
  for (const char* method : {"zslab-hybrid", "mdvr", "peel", "reference"}) {
    const Image image = render_scene(from_side, 80, bundle(dir, "inside"), method);
    // 2 pixels per mm; a tube at RAS (y, z) is at pixel (40 + 2y, 40 - 2z).
    for (float ry : test::kBundleRowsY)
      for (float z : test::kBundleRowsZ) {
        const int px = static_cast<int>(40 + 2 * ry), py = static_cast<int>(40 - 2 * z);
        const glm::vec4 c = image.at(px, py);
        if (std::abs(ry) > 10.0f) {
          EXPECT_LT(c.a, 0.01f) << method << " " << ry << " " << z;
          continue;
        }
        const float x_ras = std::sqrt(kBall * kBall - ry * ry - z * z);
        const float cap_grey = (x_ras + test::kBundleLength) / (2.0f * test::kBundleLength);
        EXPECT_GT(c.a, 0.99f) << method << " " << ry << " " << z;
        // The map's grey is a display grey (docs/colour.md): compared as the PNG shows it.
        EXPECT_NEAR(srgb_encode(c.r), cap_grey, 0.02f) << method << " " << ry << " " << z;
        EXPECT_NEAR(c.g, c.r, 1e-3f) << "flat: the map's grey, unshaded";
        // Without the ball no such disc: the tube's near end (grey 1) or nothing.
        const glm::vec4 w = whole.at(px, py);
        EXPECT_TRUE(w.a < 0.5f || std::abs(srgb_encode(w.r) - cap_grey) > 0.1f) << ry << " " << z;
      }
    EXPECT_LT(image.at(40, 40).a, 0.01f) << method << ": between the tubes the ball shows nothing";
  }
}

TEST(StreamlineClipMesh, TheMethodsDrawTheSameCut) {
  test::TempDir dir;
  test::write_bundle(dir);
  const nlohmann::json oblique = {
      {"eye", {-120, -90, 70}}, {"target", {0, 0, 0}}, {"up", {0, 0, 1}}, {"fov_deg", 30}};
  for (bool fog : {false, true})
    for (const char* keep : {"inside", "outside"})
      for (double opacity : {1.0, 0.5}) {
        if (fog && opacity == 1.0) continue;  // translucent tubes in fog: what mixes them
        const nlohmann::json look = {{"opacity", opacity}, {"shading", {{"enabled", true}}}};
        const Image reference =
            render_scene(oblique, 96, bundle(dir, keep, look), "reference", fog);
        const Image whole = render_scene(oblique, 96, bundle(dir, "", look), "reference", fog);
        const double unclipped = psnr(reference, whole);
        // The cut changes the picture more than any method may differ from the reference.
        if (!fog) {
          EXPECT_LT(unclipped, 35.0) << keep << ": the cut changes the picture";
        }
        for (const char* method : {"zslab-hybrid", "mdvr", "peel"}) {
          const Image image = render_scene(oblique, 96, bundle(dir, keep, look), method, fog);
          const double db = psnr(image, reference);
          // Each method is far nearer the clipped reference than the unclipped picture is.
          EXPECT_LT(unclipped, db - 10.0) << keep << " " << method << " fog " << fog;
          EXPECT_GT(db, 35.0) << keep << " " << method << " opacity " << opacity << " fog " << fog
                              << " (unclipped " << unclipped << " dB)";
        }
      }
}

TEST(StreamlineClipMesh, ClipNamesAClosedMeshOfTheScene) {
  test::TempDir dir;
  test::write_bundle(dir);
  auto load = [&](const nlohmann::json& tubes, const nlohmann::json& other) {
    const nlohmann::json scene = {{"objects", {tubes, other}}};
    return parse_scene(scene.dump(), ".", "test");
  };
  const Scene ok = load(bundle(dir, "outside"), kBallObject);
  ASSERT_EQ(ok.streamlines.size(), 1u);
  ASSERT_EQ(ok.streamlines[0].clip_meshes.size(), 1u);
  EXPECT_EQ(ok.streamlines[0].clip_meshes[0].mesh, 0);
  EXPECT_FALSE(ok.streamlines[0].clip_meshes[0].keep_inside);

  nlohmann::json named_twice = bundle(dir, "inside");
  named_twice["clip"].push_back({{"mesh", "ball"}, {"keep", "outside"}});
  test::expect_error([&] { load(named_twice, kBallObject); },
                     {"'ball' is already clip[0] of streamlines 'bundle'"});
  nlohmann::json not_a_mesh = bundle(dir, "");
  not_a_mesh["clip"] = {{{"mesh", "bundle"}, {"keep", "inside"}}};
  test::expect_error([&] { load(not_a_mesh, kBallObject); }, {"clip geometry is a closed mesh"});
  nlohmann::json open = kBallObject;
  open["source"] = {{"primitive", "quad"}, {"size", {10, 10}}};
  test::expect_error([&] { load(bundle(dir, "inside"), open); }, {"is not closed"});
  // A connectome takes no clip geometry (nor clip planes): its "clip" is an unknown key.
  const nlohmann::json connectome = {{"name", "net"},
                                     {"type", "connectome"},
                                     {"source", {{"file", "net.jcon"}}},
                                     {"clip", {{{"mesh", "ball"}, {"keep", "inside"}}}}};
  test::expect_error([&] { load(connectome, kBallObject); }, {"objects[0].clip: unknown key"});
}

}  // namespace
}  // namespace imx
