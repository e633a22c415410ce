// peel with opaque geometry (SPEC §7): the nearest opaque fragment is a depth buffer that ends
// the ray and every peel pass; only the transparent fragments in front of it are peeled.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <vector>

#include "../slab/slab_test_util.hpp"
#include "homogeneous_volume.hpp"
#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "methods/fragment/peel_kernel.hpp"
#include "methods/reference/reference_kernel.hpp"

namespace imx {
namespace {

using test::near4;

glm::vec4 colour(float r, float g, float b, float a) {
  return {r * a, g * a, b * a, a};
}

// Front-to-back over of the fragments in the order given.
glm::vec4 over_all(const std::vector<Fragment>& f) {
  glm::vec4 c(0.0f);
  for (const Fragment& x : f) c = over(c, x.color);
  return c;
}

struct PeelRay {
  std::vector<Slab> layers = std::vector<Slab>(64), a = std::vector<Slab>(256),
                    b = std::vector<Slab>(256);
  HybridParams hp;
  Ray ray{{0, 0, 0}, {0, 0, 1}};
  PeelRay() { hp.ert = 1.0f; }  // no early termination: only the opaque depth may end a ray
  glm::vec4 operator()(std::vector<Fragment> f, int l, bool unsorted = false,
                       std::span<const PreparedVolume> v = {}) {
    return trace_peel(ray, f, {l, unsorted}, v, {}, hp, layers, {a, b});
  }
};

// Five transparent fragments at 10..50 mm, an opaque one at 60 and two transparent ones behind.
struct ImplantRay {
  std::vector<Fragment> front, behind;
  Fragment opaque{60.0f, colour(0.7f, 0.7f, 0.8f, 1.0f), 5, 1};
  ImplantRay() {
    for (int i = 0; i < 5; ++i)
      front.push_back(
          {10.0f + 10.0f * i, colour(0.2f * i, 1.0f - 0.2f * i, 0.5f, 0.3f), uint32_t(i), 1});
    behind = {{70.0f, colour(1, 0, 0, 0.5f), 6, 0}, {80.0f, colour(0, 1, 0, 0.5f), 7, 0}};
  }
  std::vector<Fragment> arrival(unsigned seed) const {
    std::vector<Fragment> f = front;
    f.insert(f.end(), behind.begin(), behind.end());
    f.push_back(opaque);
    std::mt19937 gen(seed);
    std::shuffle(f.begin(), f.end(), gen);
    return f;
  }
};

TEST(PeelOpaque, OpaqueBehindMoreTransparentLayersThanLIsStillComposited) {
  PeelRay peel;
  ImplantRay r;
  // L = 4: the fifth transparent fragment is lost, the opaque one is not
  std::vector<Fragment> want = {r.front[0], r.front[1], r.front[2], r.front[3], r.opaque};
  for (unsigned seed = 0; seed < 8; ++seed) {
    glm::vec4 got = peel(r.arrival(seed), 4);
    EXPECT_TRUE(near4(got, over_all(want), 1e-6f)) << seed;
    EXPECT_FLOAT_EQ(got.a, 1.0f);
  }
  // with room for every transparent layer it is exact
  std::vector<Fragment> all = r.front;
  all.push_back(r.opaque);
  EXPECT_TRUE(near4(peel(r.arrival(1), 5), over_all(all), 1e-6f));
}

TEST(PeelOpaque, FragmentsBehindTheOpaqueOneUseNoLayers) {
  PeelRay peel;
  ImplantRay r;
  r.front.resize(2);
  std::vector<Fragment> want = {r.front[0], r.front[1], r.opaque};
  std::vector<Fragment> f = r.arrival(3);
  f.push_back({65.0f, colour(0, 0, 1, 1.0f), 8, 1});  // a second opaque surface, hidden
  for (int l : {2, 3, 8}) {
    EXPECT_TRUE(near4(peel(f, l), over_all(want), 1e-6f)) << l;
    EXPECT_TRUE(near4(peel(f, l, true), over_all(want), 1e-6f)) << l;  // no rest in front
  }
  // the nearest opaque fragment wins whatever the arrival order
  std::reverse(f.begin(), f.end());
  EXPECT_TRUE(near4(peel(f, 2), over_all(want), 1e-6f));
  // an opaque fragment in front of everything is all there is
  f.push_back({5.0f, colour(1, 1, 1, 1.0f), 9, 1});
  EXPECT_TRUE(near4(peel(f, 4), f.back().color, 1e-6f));
}

TEST(PeelOpaque, UnsortedRestStopsAtTheOpaqueDepth) {
  PeelRay peel;
  ImplantRay r;
  std::vector<Fragment> f = r.arrival(5);
  // two layers, then the other transparent fragments in front of the opaque one blended in
  // arrival order, then the opaque one; the two behind it stay hidden
  std::vector<Fragment> rest;
  for (const Fragment& x : f)
    if (x.t > r.front[1].t && x.t < r.opaque.t) rest.push_back(x);
  ASSERT_EQ(rest.size(), 3u);
  glm::vec4 want = over(over(over_all({r.front[0], r.front[1]}), over_all(rest)), r.opaque.color);
  EXPECT_TRUE(near4(peel(f, 2, true), want, 1e-6f));
  // with the rest lost, the opaque fragment still ends the two layers
  EXPECT_TRUE(near4(peel(f, 2), over_all({r.front[0], r.front[1], r.opaque}), 1e-6f));
}

TEST(PeelOpaque, OpaqueSurfaceEndsTheVolumeSegment) {
  // a homogeneous medium over t in [90, 110], cast in 1 mm steps; an opaque surface at 100.3 lands
  // on the step boundary at 100, and nothing of the medium behind it shows
  PeelRay peel;
  peel.ray = Ray{{0.3f, 0.2f, -100.0f}, {0, 0, 1}};
  peel.hp.step = 1.0f;
  VolumeObject obj = test::homogeneous_volume(0.1f, {0.2f, 0.4f, 1.0f});
  std::vector<PreparedVolume> vols{PreparedVolume(obj)};
  const glm::vec4 red = colour(1, 0, 0, 0.4f), grey = colour(0.6f, 0.6f, 0.6f, 1.0f);
  std::vector<Fragment> f = {
      {104.0f, colour(0, 1, 0, 0.5f), 2, 1}, {100.3f, grey, 1, 1}, {95.0f, red, 0, 1}};
  ReferenceParams rp;
  rp.step = 0.05;
  rp.ert = 1.0f;
  std::vector<Fragment> snapped = {{95.0f, red, 0, 1}, {100.0f, grey, 1, 1}};
  glm::vec4 want = trace_reference(peel.ray, snapped, vols, {}, rp);
  for (int l : {1, 4}) {
    glm::vec4 got = peel(f, l, false, vols);
    EXPECT_TRUE(near4(got, want, 2e-3f)) << l;
    EXPECT_FLOAT_EQ(got.a, 1.0f);
  }
  // the medium in front does show: 5 mm of it between the red surface and the opaque one
  EXPECT_FALSE(near4(peel(f, 1, false, vols), over(red, grey), 1e-2f));
}

Scene implant_shells(std::vector<std::string> overrides = {}) {
  overrides.push_back("image.width=64");
  overrides.push_back("image.height=64");
  return load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "implant-shells.json", overrides);
}

Image render_with(const Scene& scene, const std::string& method) {
  RenderOptions options;
  options.method = method;
  return render(scene, options);
}

TEST(PeelOpaque, ImplantShowsThroughFourShellsAtFourLayers) {
  // zoomed on the screw head so that every sample ray ends on it, behind four shells
  const std::vector<std::string> head = {"camera.target=[7.5, 0, 13]", "camera.fov_deg=1",
                                         "render.peel_layers=4", "render.peel_rest=lost"};
  Scene scene = implant_shells(head);
  EXPECT_GE(psnr(render_with(scene, "peel"), render_with(scene, "dfb")), 50.0);
  // the view is one where a lost implant shows: the same head at opacity 0.99 is peeled as a
  // fifth transparent layer and lost
  std::vector<std::string> glassy = head;
  glassy.push_back("objects.screw-head.material.opacity=0.99");
  Scene lost = implant_shells(glassy);
  EXPECT_LT(psnr(render_with(lost, "peel"), render_with(lost, "dfb")), 30.0);
}

TEST(PeelOpaque, WholeSceneMatchesDfbAtTheDefaults) {
  // four layers, the rest blended unsorted: the shells' back faces beside the screw are the
  // fifth to eighth layers
  Scene scene = implant_shells();
  ASSERT_EQ(scene.render.peel_layers, 4);
  EXPECT_GE(psnr(render_with(scene, "peel"), render_with(scene, "dfb")), 50.0);
  Scene lost = implant_shells({"render.peel_rest=lost"});
  EXPECT_LT(psnr(render_with(lost, "peel"), render_with(lost, "dfb")), 40.0);
}

TEST(PeelOpaque, WholeSceneMatchesDfbWithRoomForEveryTransparentLayer) {
  Scene scene = implant_shells({"render.peel_layers=8"});
  Image truth = render_with(scene, "dfb");
  EXPECT_GE(psnr(render_with(scene, "peel"), truth), 50.0);
}

}  // namespace
}  // namespace imx
