// CSG scenes with analytic answers, rendered by csg and by the reference (CSG.md §5, A1-A5,
// Q1-Q7): exact pixel counts, areas, equivalences and agreement with the reference.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "probes/z_fighting_probe.hpp"

namespace imx {
namespace {

Scene scene_from(const std::string& json, std::vector<std::string> overrides = {}) {
  return parse_scene(json, ".", "csg-test.json", overrides);
}

Image render_with(const Scene& scene, const std::string& method, int spp = 0) {
  RenderOptions options;
  options.method = method;
  options.spp = spp;
  return render(scene, options);
}

// Unshaded, opaque material of one colour.
std::string flat(const char* rgb, double opacity = 1.0) {
  return fmt::format(R"({{"color": {}, "opacity": {}, "shading": {{"enabled": false}}}})", rgb,
                     opacity);
}

// An orthographic camera with 1 mm pixels looking at the origin from `eye`, a transparent
// background (so that alpha is coverage), and `objects` / `csg` as given.
std::string ortho_scene(const std::string& eye, const std::string& up, int pixels,
                        const std::string& objects, const std::string& csg) {
  return fmt::format(
      R"({{"camera": {{"eye": {}, "target": [0, 0, 0], "up": {}, "projection": "orthographic",
                      "ortho_height": {}}},
          "image": {{"width": {}, "height": {}, "background": [0, 0, 0, 0]}},
          "objects": [{}], "csg": {}}})",
      eye, up, pixels, pixels, pixels, objects, csg);
}

// Pixels whose coverage is at least `alpha`, and the sum of coverage.
struct Coverage {
  int opaque = 0;
  double sum = 0.0;
  int of_colour = 0;  // opaque pixels whose strongest channel is `channel`
};
Coverage coverage(const Image& image, int channel = 0) {
  Coverage c;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const glm::vec4 p = image.at(x, y);
      c.sum += p.a;
      if (p.a > 0.999f) {
        ++c.opaque;
        if (p[channel] > 0.99f) ++c.of_colour;
      }
    }
  return c;
}

// A1: a 40 mm cube minus a 20 x depth x 20 mm box through it along the view.
std::string box_with_hole(double cutter_depth, const std::string& eye = "[0, 200, 0]",
                          const std::string& up = "[0, 0, 1]") {
  const std::string objects = fmt::format(
      R"({{"name": "part", "type": "mesh", "source": {{"primitive": "box", "size": 40}},
          "material": {}}},
         {{"name": "cutter", "type": "mesh",
          "source": {{"primitive": "box", "size": [20, {}, 20]}}, "material": {}}})",
      flat("[1, 0, 0]"), cutter_depth, flat("[0, 1, 0]"));
  return ortho_scene(eye, up, 64, objects, R"({"op": "difference", "a": "part", "b": "cutter"})");
}

TEST(CsgRender, BoxWithASquareHoleHasItsExactPixelCount) {  // A1
  for (double depth : {60.0, 40.0}) {  // 40: the cutter's front and back share the part's faces
    const Scene scene = scene_from(box_with_hole(depth));
    for (const char* method : {"csg", "reference"}) {
      const Coverage c = coverage(render_with(scene, method, 1));
      EXPECT_EQ(c.opaque, 1200) << method << " depth " << depth;
      EXPECT_EQ(c.of_colour, 1200) << method << " depth " << depth;
      EXPECT_NEAR(c.sum, 1200.0, 1e-3) << method << " depth " << depth;
    }
  }
}

TEST(CsgRender, RotatedGrazingViewMatchesTheReference) {  // Q7
  // The A1 scene seen rotated about the view axis and tilted, so that faces graze.
  const double tilt = 17.0 * std::numbers::pi / 180.0, roll = 30.0 * std::numbers::pi / 180.0;
  const std::string eye =
      fmt::format("[{}, {}, {}]", 0.0, 200.0 * std::cos(tilt), 200.0 * std::sin(tilt));
  const std::string up = fmt::format("[{}, {}, {}]", std::sin(roll), 0.0, std::cos(roll));
  const Scene scene = scene_from(box_with_hole(40.0, eye, up));
  const Image fast = render_with(scene, "csg", 1);
  const Image truth = render_with(scene, "reference", 1);
  EXPECT_LT(compare_images(fast, truth).frac_over_16, 0.001);
}

TEST(CsgRender, SphereMeshMinusAHalfSpaceShowsTheCutFaceInTheCuttersColour) {  // A2
  // A UV sphere of radius 40 and 64 segments minus the box x > 0. Its section at x = 0 is a
  // regular 64-gon of area 32 R^2 sin(2 pi / 64) (the disk would be 5026.5 mm^2).
  const std::string objects =
      R"({"name": "ball", "type": "mesh", "source": {"primitive": "sphere", "radius": 40,
          "segments": 64}, "material": )" +
      flat("[1, 0, 0]") + R"(}, {"name": "half", "type": "mesh",
          "source": {"primitive": "box", "size": [100, 200, 200]},
          "transform": {"translate": [50, 0, 0]}, "material": )" +
      flat("[0, 1, 0]") + "}";
  const std::string csg = R"({"op": "difference", "a": "ball", "b": "half"})";
  const double section = 32.0 * 40.0 * 40.0 * std::sin(2.0 * std::numbers::pi / 64.0);
  // Seen from the cut side: the cut face, which belongs to the cutter.
  const Image cut = render_with(
      scene_from(ortho_scene("[300, 0, 0]", "[0, 0, 1]", 128, objects, csg)), "csg", 16);
  Coverage c = coverage(cut, 1);
  EXPECT_NEAR(c.sum, section, 0.003 * section);
  EXPECT_EQ(c.of_colour, c.opaque);
  // From the other side: the same outline in the sphere's colour.
  const Image back = render_with(
      scene_from(ortho_scene("[-300, 0, 0]", "[0, 0, 1]", 128, objects, csg)), "csg", 16);
  c = coverage(back, 0);
  EXPECT_NEAR(c.sum, section, 0.003 * section);
  EXPECT_EQ(c.of_colour, c.opaque);
}

// A3: the sphere phantom (value 44.8 mm - |p|) as an opaque ball, minus the half-space x > 0.
std::string half_ball(const char* op) {
  const std::string objects = R"(
    {"name": "ball", "type": "volume", "source": {"phantom": "sphere", "size": 128},
     "transfer_function": {"points": [[0, 1, 1, 1, 0], [0.5, 1, 1, 1, 1]]}},
    {"name": "half", "type": "mesh", "source": {"primitive": "box", "size": [100, 200, 200]},
     "transform": {"translate": [50, 0, 0]}, "material": )" +
                              flat("[0, 1, 0]", 0.0) + "}";
  return ortho_scene("[0, 0, 300]", "[0, 1, 0]", 128, objects,
                     fmt::format(R"({{"op": "{}", "a": "ball", "b": "half"}})", op));
}

TEST(CsgRender, BallMinusAHalfSpaceCoversHalfTheDisk) {  // A3
  const double half_disk = std::numbers::pi * 44.8 * 44.8 / 2.0;
  double total = 0.0;
  // Under the sanitizers the csg method only: the reference's two half balls at 128 x 128 and 4
  // samples were most of the test's 60 s there; its numbers are checked in the release build, and
  // its CSG code runs under the sanitizers in A5 and Q3 of this file.
#ifdef IMX_SANITIZED
  const char* const methods[] = {"csg"};
#else
  const char* const methods[] = {"csg", "reference"};
#endif
  for (const char* op : {"difference", "intersection"})
    for (const char* method : methods) {
      const Coverage c = coverage(render_with(scene_from(half_ball(op)), method, 4));
      EXPECT_NEAR(c.sum, half_disk, 0.02 * half_disk) << op << " " << method;
      if (std::string(method) == "csg") total += c.sum;
    }
  EXPECT_NEAR(total, 2.0 * half_disk, 0.02 * half_disk);
}

// A5: a fog volume minus (or united with) a slab mesh, per ray in closed form.
std::string fog_and_slab(const char* op, double slab_opacity) {
  // A 20 mm thick fog of opacity 0.05 per mm along the view, and a 6 mm slab mesh inside it.
  const std::string objects = fmt::format(
      R"({{"name": "fog", "type": "volume", "source": {{"phantom": "cube", "size": 32}},
          "transform": {{"scale": [1, 1, 0.15625]}},
          "transfer_function": {{"points": [[0, 1, 1, 1, 0.05], [255, 1, 1, 1, 0.05]]}}}},
         {{"name": "slab", "type": "mesh", "source": {{"primitive": "box", "size": [200, 200, 6]}},
          "material": {}, "interior": {{"color": [0, 0, 1], "opacity": {}}}}})",
      flat("[0, 1, 0]", 0.0), slab_opacity);
  return ortho_scene("[0, 0, 300]", "[0, 1, 0]", 8, objects,
                     fmt::format(R"({{"op": "{}", "a": "fog", "b": "slab"}})", op));
}

TEST(CsgRender, FogMinusASlabIsThinnerFogInClosedForm) {  // A5
  // The cube phantom at 32 has 4 mm voxels, so its box of voxel centres spans 124 mm; scaled in
  // z by 0.15625 it is 19.375 mm deep.
  const double depth = 124.0 * 0.15625;
  for (const char* method : {"csg", "reference"}) {
    const Image minus = render_with(scene_from(fog_and_slab("difference", 0.3)), method, 1);
    EXPECT_NEAR(minus.at(4, 4).a, 1.0 - std::pow(0.95, depth - 6.0), 2e-3) << method;
    const Image united = render_with(scene_from(fog_and_slab("union", 0.3)), method, 1);
    EXPECT_NEAR(united.at(4, 4).a, 1.0 - std::pow(0.95, depth) * std::pow(0.7, 6.0), 2e-3)
        << method;
  }
}

// Q1 and Q2 on the two-volumes example.
Scene two_volumes(const std::string& csg, std::vector<std::string> more = {}) {
  more.insert(more.begin(),
              {"image.width=96", "image.height=96", "render.packets=false", "csg=" + csg});
  return load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "two-volumes.json", more);
}

bool identical(const Image& a, const Image& b) {
  return std::equal(a.data(), a.data() + a.width() * a.height(), b.data(),
                    [](const glm::vec4& p, const glm::vec4& q) { return p == q; });
}

TEST(CsgRender, UnionOfAllVolumesIsMdvrBitForBit) {  // Q1
  const Scene scene = two_volumes(R"({"op": "union", "a": "cube", "b": "ellipsoid"})");
  EXPECT_TRUE(identical(render_with(scene, "csg"), render_with(two_volumes("null"), "mdvr")));
}

TEST(CsgRender, EquivalentStateTablesGiveIdenticalImages) {  // Q2
  const std::string expr = R"({"op": "union", "a": "cube", "b": "ellipsoid"})";
  const Image merged = render_with(two_volumes(expr, {"render.csg_simplify=merge"}), "csg");
  EXPECT_TRUE(
      identical(render_with(two_volumes(expr, {"render.csg_simplify=full"}), "csg"), merged));
  // The same set as three minterms, not simplified.
  const std::string minterms =
      R"({"op": "union", "of": [{"op": "difference", "a": "cube", "b": "ellipsoid"},
                                {"op": "intersection", "a": "cube", "b": "ellipsoid"},
                                {"op": "difference", "a": "ellipsoid", "b": "cube"}]})";
  EXPECT_TRUE(
      identical(render_with(two_volumes(minterms, {"render.csg_simplify=none"}), "csg"), merged));
}

TEST(CsgRender, DifferenceOfVolumesMatchesTheReference) {  // Q3 on volumes
  const Scene scene = two_volumes(R"({"op": "difference", "a": "cube", "b": "ellipsoid"})",
                                  {"image.width=64", "image.height=64"});
  const Image fast = render_with(scene, "csg", 4);
  const Image truth = render_with(scene, "reference", 4);
  EXPECT_GE(psnr(fast, truth), 40.0);
  // And it is not the union: the ellipsoid's part is gone.
  const Scene both = two_volumes(R"({"op": "union", "a": "cube", "b": "ellipsoid"})",
                                 {"image.width=64", "image.height=64"});
  EXPECT_LT(psnr(fast, render_with(both, "csg")), 30.0);
}

TEST(CsgRender, EyeInsideACutterMatchesTheReference) {  // Q6
  // The camera sits inside the cutter ball of `ball-phantom - cutter`.
  const std::string objects = R"(
    {"name": "ball", "type": "volume", "source": {"phantom": "sphere", "size": 64},
     "transfer_function": {"points": [[0, 1, 0.8, 0.6, 0], [2, 1, 0.8, 0.6, 0.3]]}},
    {"name": "cutter", "type": "mesh", "source": {"primitive": "sphere", "radius": 80},
     "transform": {"translate": [0, -90, 0]}, "material": )" +
                              flat("[0, 1, 0]", 0.3) + "}";
  const std::string json = fmt::format(
      R"({{"camera": {{"eye": [0, -100, 0], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 60}},
          "image": {{"width": 48, "height": 48}},
          "objects": [{}], "csg": {{"op": "difference", "a": "ball", "b": "cutter"}}}})",
      objects);
  const Scene scene = scene_from(json);
  // Both supersampled alike, so that the ball's rim does not decide.
  const Image fast = render_with(scene, "csg", 4);
  const Image truth = render_with(scene, "reference", 4);
  EXPECT_GE(psnr(fast, truth), 40.0);
  // The cut-away near half shows the ball's inside: the centre is not the uncut ball's.
  const Image uncut = render_with(scene_from(json, {"csg=null"}), "mdvr");
  EXPECT_GT(std::abs(fast.at(24, 24).g - uncut.at(24, 24).g), 0.01f);
}

TEST(CsgRender, OtherMethodsRefuseACsgScene) {
  const Scene scene = scene_from(box_with_hole(60.0));
  for (const char* method : {"mdvr", "peel", "dfb", "zslab-hybrid"}) {
    try {
      render_with(scene, method, 1);
      ADD_FAILURE() << method << " rendered a CSG scene";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("does not render CSG"), std::string::npos) << e.what();
    }
  }
}

TEST(CsgRender, AnExpressionEmptyForTheBoundsIsAnError) {
  // The cutter box lies beside the part: part ∩ cutter is empty.
  const Scene scene =
      scene_from(box_with_hole(60.0),
                 {"objects.cutter.transform.translate=[100, 0, 0]", "csg.op=intersection"});
  try {
    render_with(scene, "csg", 1);
    ADD_FAILURE() << "rendered an empty expression";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
  }
}

TEST(CsgRender, ExclusiveMixingFollowsThePriorityAndMatchesTheReference) {  // Q8
  auto mixing = [](const std::string& priority) {
    return load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "csg-mixing.json",
                      {"image.width=48", "image.height=48", "render.mixing_priority=" + priority});
  };
  const Scene skin_first = mixing(R"(["skin"])");
  const Image fast = render_with(skin_first, "csg", 4);
  EXPECT_GE(psnr(fast, render_with(skin_first, "reference", 4)), 40.0);
  // Priority to the bone instead, and inclusive mixing, give other images.
  EXPECT_LT(psnr(fast, render_with(mixing(R"(["bone"])"), "csg", 4)), 30.0);
  Scene inclusive = skin_first;
  inclusive.render.mixing = "inclusive";
  EXPECT_LT(psnr(fast, render_with(inclusive, "csg", 4)), 30.0);
}

TEST(CsgRender, MethodsThatMixInclusivelyRefuseExclusiveMixing) {
  Scene scene = load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "two-volumes.json",
                           {"image.width=8", "image.height=8", "render.mixing=exclusive"});
  EXPECT_NO_THROW(render_with(scene, "csg"));
  try {
    render_with(scene, "mdvr");
    ADD_FAILURE() << "mdvr mixed exclusively";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("inclusively only"), std::string::npos) << e.what();
  }
}

TEST(CsgRender, ACoplanarCutterShowsNoZFighting) {  // A1, shared faces
  RenderOptions options;
  options.method = "csg";
  options.spp = 1;
  const ZFightingStats s = measure_z_fighting(scene_from(box_with_hole(40.0)), options);
  EXPECT_GT(s.pixels, 200);
  EXPECT_LT(s.std_dev, 1e-6);
  EXPECT_LT(s.speckle, 1e-6);
  EXPECT_LT(s.jitter_change, 1e-6);
}

TEST(CsgRender, SixtyFourPrimitivesWorkUpToTheLast) {  // A6
  // A 120 x 10 x 120 box minus 63 cylinders through it on an 8 x 8 grid of 14 mm (one cell
  // left solid); the last cylinder is primitive 63.
  std::string objects = R"({"name": "plate", "type": "mesh",
      "source": {"primitive": "box", "size": [120, 10, 120]}, "material": )" +
                        flat("[1, 0, 0]") + "}";
  std::string holes;
  std::vector<glm::ivec2> centres;
  for (int cell = 1; cell < 64; ++cell) {
    const glm::ivec2 c(-49 + 14 * (cell % 8), -49 + 14 * (cell / 8));
    centres.push_back(c);
    const std::string name = fmt::format("hole{}", cell);
    objects += fmt::format(
        R"(, {{"name": "{}", "type": "mesh",
              "source": {{"primitive": "cylinder", "radius": 3, "height": 30, "segments": 24}},
              "transform": {{"translate": [{}, 0, {}], "rotate_deg": [90, 0, 0]}},
              "material": {}}})",
        name, c.x, c.y, flat("[0, 1, 0]", 0.0));
    holes += (holes.empty() ? "\"" : ", \"") + name + "\"";
  }
  const Scene scene =
      scene_from(ortho_scene("[0, 200, 0]", "[0, 0, 1]", 128, objects,
                             fmt::format(R"({{"op": "difference", "of": ["plate", {}]}})", holes)));
  const Image image = render_with(scene, "csg", 1);
  // World x runs to the image's left when looking along -y with z up; z runs up.
  auto pixel = [&](glm::ivec2 c) { return image.at(63 - c.x, 63 - c.y); };
  for (const glm::ivec2& c : centres) EXPECT_EQ(pixel(c).a, 0.0f) << c.x << ", " << c.y;
  EXPECT_GT(pixel({-49, -49}).a, 0.99f);  // the solid cell
  EXPECT_GT(pixel({-42, -42}).a, 0.99f);  // between holes
}

TEST(CsgRender, TooManyStatesIsAnErrorNamingTheCount) {
  // (a1 ∪ b1) ∩ ... ∩ (a13 ∪ b13) expands to 2^13 = 8192 products.
  std::string objects, expr;
  for (int k = 0; k < 13; ++k) {
    for (const char* side : {"a", "b"})
      objects += fmt::format(
          R"({}{{"name": "{}{}", "type": "mesh", "source": {{"primitive": "sphere", "radius": 10}},
                "material": {}}})",
          objects.empty() ? "" : ", ", side, k, flat("[1, 1, 1]"));
    const std::string pair = fmt::format(R"({{"op": "union", "a": "a{}", "b": "b{}"}})", k, k);
    expr = expr.empty() ? pair
                        : fmt::format(R"({{"op": "intersection", "a": {}, "b": {}}})", expr, pair);
  }
  const Scene scene = scene_from(ortho_scene("[0, 200, 0]", "[0, 0, 1]", 8, objects, expr));
  try {
    render_with(scene, "csg", 1);
    ADD_FAILURE() << "rendered 8192 products";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("8192"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("4096"), std::string::npos) << e.what();
  }
}

TEST(CsgRender, ImagesDoNotDependOnTheThreadCount) {  // Q5
  const Scene scene = load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "csg-cutaway.json",
                                 {"image.width=40", "image.height=40"});
  for (const char* method : {"csg", "reference"}) {
    RenderOptions options;
    options.method = method;
    options.spp = 4;
    options.threads = 1;
    const Image one = render(scene, options);
    options.threads = 2;
    EXPECT_TRUE(identical(one, render(scene, options))) << method;
  }
}

}  // namespace
}  // namespace imx
