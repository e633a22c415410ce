// Streamline objects as CSG primitives: the inside of their tubes is a region, so a box minus a
// tube has a hole where the tube passes through it, and a ball intersected with tubes shows the
// tubes only inside the ball, capped by the ball's surface, in the csg method and the reference.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "core/colour.hpp"
#include "expect_error.hpp"
#include "intermix/error.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "mrtrix_tracks.hpp"
#include "streamline_bundle.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

// Two straight streamlines, a point every 2 mm (the file is RAS: x and y negated): one from LPS
// (0, 0, -20) to (3, 0, 20) (tilted: a ray along a tube's axis meets nothing,
// docs/streamlines.md), and one along x from -15 to 15 at y = -12, z = 10, above the slab below.
void write_tube(const std::filesystem::path& tck) {
  std::vector<std::vector<float>> points(2);
  for (int i = 0; i <= 20; ++i) {
    const float s = i / 20.0f;
    points[0].insert(points[0].end(), {-3.0f * s, 0.0f, -20.0f + 40.0f * s});
  }
  for (int i = 0; i <= 15; ++i) points[1].insert(points[1].end(), {15.0f - 2.0f * i, 12.0f, 10.0f});
  test::write_mrtrix_tracks(tck, "mrtrix tracks", points, 3);
}

// The tube's axis at height z (LPS).
glm::dvec2 axis_at(double z) {
  return {3.0 * (z + 20.0) / 40.0, 0.0};
}

constexpr double kRadius = 3.0;

nlohmann::json tube(const test::TempDir& dir, double opacity) {
  return {{"name", "tracts"},
          {"type", "streamlines"},
          {"source", {{"file", (dir / "tube.tck").string()}}},
          {"radius", kRadius},
          {"color", {1, 0, 0}},
          {"opacity", opacity},
          {"shading", {{"enabled", false}}}};
}

Image render_scene(const std::vector<nlohmann::json>& objects, const nlohmann::json& csg,
                   const char* method) {
  nlohmann::json scene = {
      {"camera", test::kFromAbove},
      {"image", {{"width", 100}, {"height", 100}, {"background", {0, 0, 0, 0}}}},
      {"render", {{"method", method}, {"spp", 1}}},
      {"objects", objects}};
  if (!csg.is_null()) scene["csg"] = csg;
  return render(parse_scene(scene.dump(), ".", "test"));
}

// A slab 40 x 40 mm, 10 mm thick (z from -5 to 5), opaque grey, unshaded.
const nlohmann::json kBox = {
    {"name", "brain"},
    {"type", "mesh"},
    {"source", {{"primitive", "box"}, {"size", {40, 40, 10}}}},
    {"material", {{"color", {0.5, 0.5, 0.5}}, {"opacity", 1}, {"shading", {{"enabled", false}}}}}};

TEST(StreamlineCsg, ABoxMinusATubeHasAHoleWhereTheTubePasses) {
  test::TempDir dir;
  write_tube(dir / "tube.tck");
  const nlohmann::json difference = {{"op", "difference"}, {"a", "brain"}, {"b", "tracts"}};
  for (const char* method : {"csg", "reference"}) {
    const Image whole = render_scene({kBox, tube(dir, 1.0)}, nullptr, method);
    const Image cut = render_scene({kBox, tube(dir, 1.0)}, difference, method);
    // A vertical ray within 2 mm of the axis at both faces lies in the tube through the whole
    // slab: it sees through. Beyond 3.5 mm of it at both faces it meets the slab's top, also
    // under the tube above the slab, which cuts nothing (its exit closes it: a tube is drawn
    // and subtracts only where it bounds the difference).
    size_t hole = 0, hole_wrong = 0, slab = 0, slab_wrong = 0;
    for (int y = 0; y < 100; ++y)
      for (int x = 0; x < 100; ++x) {
        const glm::dvec2 p = glm::dvec2(test::world_from_above(x, y));
        if (std::abs(p.x) > 19.0 || std::abs(p.y) > 19.0) continue;  // the slab's edges
        ASSERT_GT(whole.at(x, y).a, 0.99f) << method << ": without csg the slab is whole";
        const double d = std::max(glm::length(p - axis_at(-5.0)), glm::length(p - axis_at(5.0)));
        const double near = std::min(glm::length(p - axis_at(-5.0)), glm::length(p - axis_at(5.0)));
        if (d < 2.0) {
          ++hole;
          hole_wrong += cut.at(x, y).a > 0.01f;
        } else if (near > 3.5) {
          ++slab;
          // The slab shows its material colour as given (a display colour: docs/colour.md).
          slab_wrong +=
              std::abs(srgb_encode(cut.at(x, y).r) - 0.5f) > 0.01f || cut.at(x, y).a < 0.99f;
        }
      }
    ASSERT_GE(hole, 6u) << method;  // the geometry is what the test thinks
    ASSERT_GT(slab, 1000u) << method;
    EXPECT_EQ(hole_wrong, 0u) << method << ": the hole is filled";
    EXPECT_EQ(slab_wrong, 0u) << method << ": the slab is cut where the tube is not";
  }
}

TEST(StreamlineCsg, OverlappingTubesCountTheirWindings) {
  // Two tilted tubes 1 mm apart (radius 3): where both hold a ray (winding 2) the slab is cut
  // as where one does; parity would leave the slab there.
  test::TempDir dir;
  std::vector<std::vector<float>> points(2);
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i <= 20; ++i) {
      const float s = i / 20.0f;
      points[k].insert(points[k].end(), {-3.0f * s - 1.0f * k, 0.0f, -20.0f + 40.0f * s});
    }
  test::write_mrtrix_tracks(dir / "tube.tck", "mrtrix tracks", points, 3);
  const nlohmann::json difference = {{"op", "difference"}, {"a", "brain"}, {"b", "tracts"}};
  for (const char* method : {"csg", "reference"}) {
    const Image cut = render_scene({kBox, tube(dir, 1.0)}, difference, method);
    size_t both = 0, both_wrong = 0;
    for (int y = 0; y < 100; ++y)
      for (int x = 0; x < 100; ++x) {
        const glm::dvec2 p = glm::dvec2(test::world_from_above(x, y));
        double d = 0.0;  // the farthest of the two axes, at either face of the slab
        for (double z : {-5.0, 5.0})
          for (double shift : {0.0, 1.0})
            d = std::max(d, glm::length(p - axis_at(z) - glm::dvec2(shift, 0.0)));
        if (d < 2.0) {
          ++both;
          both_wrong += cut.at(x, y).a > 0.01f;
        }
      }
    ASSERT_GE(both, 3u) << method;
    EXPECT_EQ(both_wrong, 0u) << method << ": the slab stays where both tubes overlap";
  }
}

TEST(StreamlineCsg, TubesIntersectedWithABallShowOnlyInsideIt) {
  test::TempDir dir;
  write_tube(dir / "tube.tck");
  // Seen from the side (from LPS +y, orthographic, 1 pixel per mm): the tube crosses z = -20..20;
  // a ball of radius 8 keeps its part within 8 mm of the origin.
  const nlohmann::json ball = {
      {"name", "ball"},
      {"type", "mesh"},
      {"source", {{"primitive", "sphere"}, {"radius", 8}, {"segments", 96}}},
      {"material", {{"color", {0, 1, 0}}, {"opacity", 1}, {"shading", {{"enabled", false}}}}}};
  const nlohmann::json side = {{"eye", {0, 300, 0}},
                               {"target", {0, 0, 0}},
                               {"up", {0, 0, 1}},
                               {"projection", "orthographic"},
                               {"ortho_height", 100}};
  const nlohmann::json intersection = {{"op", "intersection"}, {"a", "tracts"}, {"b", "ball"}};
  for (const char* method : {"csg", "reference"}) {
    nlohmann::json scene = {
        {"camera", side},
        {"image", {{"width", 100}, {"height", 100}, {"background", {0, 0, 0, 0}}}},
        {"render", {{"method", method}, {"spp", 1}}},
        {"objects", {tube(dir, 1.0), ball}},
        {"csg", intersection}};
    const Image image = render(parse_scene(scene.dump(), ".", "test"));
    // The view's right is LPS -x: column c shows x = 50 - c - 0.5, row r shows z = 50 - r - 0.5.
    size_t inside = 0, inside_wrong = 0, outside = 0, outside_wrong = 0;
    for (int row = 0; row < 100; ++row)
      for (int col = 0; col < 100; ++col) {
        const double z = 50.0 - row - 0.5, x = 50.0 - col - 0.5;
        if (std::abs(x - axis_at(z).x) > 1.5) continue;  // near the tube's axis in the image
        const glm::vec4 c = image.at(col, row);
        if (std::abs(z) < 5.0) {  // tube inside the ball: its red wall in front
          ++inside;
          inside_wrong += c.a < 0.99f || c.r < 0.99f || c.g > 0.01f;
        } else if (std::abs(z) > 10.0) {  // tube outside the ball: nothing
          ++outside;
          outside_wrong += c.a > 0.01f;
        }
      }
    ASSERT_GE(inside, 20u) << method;
    ASSERT_GE(outside, 40u) << method;
    EXPECT_EQ(inside_wrong, 0u) << method;
    EXPECT_EQ(outside_wrong, 0u) << method;
  }
}

TEST(StreamlineCsg, TubesArePresentAsARegionAndAConnectomeIsNoPrimitive) {
  test::TempDir dir;
  write_tube(dir / "tube.tck");
  nlohmann::json scene = {{"objects", {kBox, tube(dir, 1.0)}},
                          {"csg", {{"op", "difference"}, {"a", "brain"}, {"b", "tracts"}}}};
  const Scene ok = parse_scene(scene.dump(), ".", "test");
  ASSERT_TRUE(ok.csg.has_value());
  scene["csg"]["b"] = {{"object", "tracts"}, {"presence", "opacity"}};
  test::expect_error([&] { parse_scene(scene.dump(), ".", "test"); },
                     {"streamlines 'tracts' can only have presence \"region\""});
  // Four nodes and their edges (BrainNet): spheres and tubes, but no region of its own.
  {
    std::ofstream node(dir / "net.node");
    node << "40 20 0 1 1 A\n-40 20 0 1 1 B\n40 -20 0 1 1 C\n-40 -20 0 1 1 D\n";
    std::ofstream edge(dir / "net.edge");
    edge << "0 3 0 0\n3 0 0 0\n0 0 0 3\n0 0 3 0\n";
  }
  const nlohmann::json net = {
      {"name", "net"},
      {"type", "connectome"},
      {"source", {{"file", (dir / "net.node").string()}, {"edges", (dir / "net.edge").string()}}}};
  const nlohmann::json with_net = {{"objects", {kBox, net}},
                                   {"csg", {{"op", "difference"}, {"a", "brain"}, {"b", "net"}}}};
  test::expect_error([&] { parse_scene(with_net.dump(), ".", "test"); },
                     {"'net' is a connectome; CSG primitives are"});
}

}  // namespace
}  // namespace imx
