// mdvr with render.packets (one volume marched 8 rays at a time) against one ray at a time.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/renderer.hpp"
#include "intermix/scene.hpp"

namespace imx {
namespace {

Image render_mdvr(Scene scene, bool packets, const std::string& method = "mdvr") {
  scene.render.packets = packets;
  RenderOptions o;
  o.method = method;
  return render(scene, o);
}

bool same_bytes(const Image& a, const Image& b) {
  return std::equal(a.data(), a.data() + a.size(), b.data());
}

// render.gradients=auto takes gradients on the fly where every ray of the frame marches in
// lanes (no copy to build or hold), and the precomputed copy where some ray marches alone: csg,
// zslab's rgba8 slabs, render.packets=false. The two differ in the copy's rounding only.
TEST(MdvrPackets, AutomaticGradientsOnTheFlyWhereEveryRayIsInLanes) {
  struct Case {
    const char* method;
    std::string extra;
    const char* expected;  // the gradient source `auto` must render the bytes of
  };
  const std::vector<Case> cases = {
      {"mdvr", "render.packets=true", "on-the-fly"},
      {"zslab", "render.packets=true", "on-the-fly"},
      {"zslab", "render.slab_format=rgba8", "precomputed"},
      {"mdvr", "render.packets=false", "precomputed"},
      {"csg", "render.mixing=exclusive", "precomputed"},  // not mdvr's path
  };
  for (const Case& c : cases) {
    auto with = [&](const std::string& gradients) {
      Scene s = load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "ct-head.json",
                           {"image.width=61", "image.height=47", "objects.ct.source.size=64",
                            c.extra, "render.gradients=" + gradients});
      RenderOptions o;
      o.method = c.method;
      return render(s, o);
    };
    const Image automatic = with("auto"), on_the_fly = with("on-the-fly"),
                precomputed = with("precomputed");
    const std::string expected = c.expected;
    EXPECT_EQ(same_bytes(automatic, on_the_fly), expected == "on-the-fly") << c.method << c.extra;
    EXPECT_EQ(same_bytes(automatic, precomputed), expected == "precomputed")
        << c.method << " " << c.extra;
  }
}

// Float reassociation only: far above what 8-bit output can show.
TEST(MdvrPackets, SameImageAsOneRayAtATime) {
  for (const std::string& extra :
       {std::string("render.skipping=distance"), std::string("render.gradients=on-the-fly"),
        std::string("render.ert_threshold=0.6")}) {
    Scene s = load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "ct-head.json",
                         {"image.width=61", "image.height=47", "objects.ct.source.size=64", extra});
    EXPECT_GE(psnr(render_mdvr(s, false), render_mdvr(s, true)), 70.0) << extra;
  }
}

// zslab and zslab-hybrid on one volume alone march it in mdvr's lanes, shaded where each
// piece's light comes from: the same image as their per-sample pipeline (two-point shading,
// greedy merges, the kernel against an empty stored array), and not mdvr's midpoint shading.
TEST(MdvrPackets, SlabMethodsOnOneVolumeSameImageAsTheirPipeline) {
  for (const std::string& extra :
       {std::string("render.skipping=distance"), std::string("render.ert_threshold=0.6"),
        std::string("render.ert_threshold=1")}) {
    Scene s = load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "ct-head.json",
                         {"image.width=61", "image.height=47", "objects.ct.source.size=64", extra});
    const Image grid = render_mdvr(s, true);
    for (const char* method : {"zslab", "zslab-hybrid"}) {
      const Image lanes = render_mdvr(s, true, method);
      EXPECT_GE(psnr(render_mdvr(s, false, method), lanes), 70.0) << extra << " " << method;
      EXPECT_LT(psnr(grid, lanes), 70.0) << extra << " " << method;  // the light's centre
    }
  }
}

// Several samples per pixel march in lanes too, a sample position at a time, and so does one
// sample of the pattern (a viewer's progressive still frames): each ray through its pixel at its
// sample's offset, the pixel the mean of its samples as the one-ray path sums them.
TEST(MdvrPackets, SamplesOfAPatternInLanes) {
  Scene s = load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "ct-head.json",
                       {"image.width=61", "image.height=47", "objects.ct.source.size=64"});
  for (const char* method : {"mdvr", "zslab"}) {
    const Image centre = render_mdvr(s, true, method);
    for (int k = -1; k < 4; ++k) {
      RenderOptions o;
      o.method = method;
      o.spp = 4;
      o.sample_index = k;  // -1: all four
      Scene lanes = s, one_by_one = s;
      lanes.render.packets = true;
      one_by_one.render.packets = false;
      const Image sample = render(lanes, o), reference = render(one_by_one, o);
      EXPECT_GE(psnr(reference, sample), 70.0) << method << " sample " << k;
      // ... and marched in lanes indeed: their float rounding shows somewhere in the bytes.
      EXPECT_FALSE(std::equal(sample.data(), sample.data() + sample.size(), reference.data()))
          << method << " sample " << k;
      EXPECT_LT(psnr(centre, sample), 50.0) << method << " sample " << k;  // off the centre
    }
  }
}

// The slab methods' volume stages beside surfaces and other volumes march in lanes too, a tile
// at a time: deferred stages collect each sample's own slabs, zslab-hybrid's last volume goes
// through each sample's intermixing kernel on the fly. The same images as one ray at a time, up
// to float rounding, with the reuse pipeline (Renderer) as well as without.
TEST(MdvrPackets, SlabMethodsVolumeStagesInLanes) {
  for (const char* example : {"ct-implant.json", "fusion.json"}) {
    Scene s = load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / example,
                         {"image.width=61", "image.height=47"});
    for (const char* method : {"zslab", "zslab-hybrid"}) {
      const Image lanes = render_mdvr(s, true, method), one_by_one = render_mdvr(s, false, method);
      EXPECT_GE(psnr(one_by_one, lanes), 70.0) << example << " " << method;
      // ... and marched in lanes indeed: their float rounding shows somewhere in the bytes.
      EXPECT_FALSE(std::equal(lanes.data(), lanes.data() + lanes.size(), one_by_one.data()))
          << example << " " << method;
      Scene reused = s;
      reused.render.packets = true;
      RenderOptions o;
      o.method = method;
      Renderer renderer;
      EXPECT_GE(psnr(one_by_one, renderer.render(reused, o)), 70.0) << example << " " << method;
    }
  }
}

// Hidden planes make no fragments, so a volume whose planes are all hidden (a viewer's reading
// planes in its 3-D view) takes the one-volume lanes: the bytes of the scene without them.
TEST(MdvrPackets, HiddenPlanesLeaveOneVolumeInLanes) {
  const std::vector<std::string> small = {"image.width=61", "image.height=47"};
  std::vector<std::string> hidden = small;
  for (const char* plane : {"axial", "coronal", "sagittal"})
    hidden.push_back(std::string("objects.") + plane + ".opacity=0");
  const Scene planes = load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "mpr.json", hidden);
  Scene alone = planes;
  alone.planes.clear();
  std::erase_if(alone.order, [](const ObjectRef& r) { return r.kind == ObjectKind::plane; });
  for (const char* method : {"mdvr", "zslab"}) {
    const Image with = render_mdvr(planes, true, method),
                without = render_mdvr(alone, true, method);
    EXPECT_TRUE(std::equal(with.data(), with.data() + with.size(), without.data())) << method;
  }
}

// With faintly visible air the box's own edges show: the packets leave out only pixels outside
// the box's projection, with the box cut by the image's edge and with the eye inside it.
TEST(MdvrPackets, LeaveOutOnlyPixelsThatMissTheBox) {
  for (const std::string& camera :
       {std::string("camera.target=[70,-20,40]"), std::string("camera.eye=[10,-30,20]")}) {
    Scene s = load_scene(
        std::filesystem::path(IMX_EXAMPLES_DIR) / "ct-head.json",
        {"image.width=61", "image.height=47", "objects.ct.source.size=64",
         "objects.ct.transfer_function.points=[[0,1,1,1,0.02],[255,1,0.5,0.5,0.6]]", camera});
    EXPECT_GE(psnr(render_mdvr(s, false), render_mdvr(s, true)), 70.0) << camera;
  }
}

}  // namespace
}  // namespace imx
