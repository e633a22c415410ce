// zslab and zslab-hybrid on small example scenes: quality against the reference, the streamed
// and the staged pipelines agreeing, stage reuse after an edit, the memory bound, and the
// render.last_volume and render.overflow settings.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "intermix/error.hpp"
#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/renderer.hpp"
#include "intermix/scene.hpp"
#include "marcher_finds.hpp"
#include "methods/zslab/zslab.hpp"
#include "methods/zslab/zslab_frame.hpp"

namespace imx {
namespace {

constexpr int kSize = 48;

Scene small(const std::string& name, std::vector<std::string> extra = {}) {
  extra.push_back("image.width=" + std::to_string(kSize));
  extra.push_back("image.height=" + std::to_string(kSize));
  return load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / (name + ".json"), extra);
}

Image render_with(const Scene& scene, const std::string& method, int spp = 1) {
  RenderOptions o;
  o.method = method;
  o.spp = spp;
  return render(scene, o);
}

TEST(ZslabRender, TwoVolumesCloseToReferenceAndNotWorseThanMdvr) {
  Scene s =
      small("two-volumes", {"objects.cube.source.size=48", "objects.ellipsoid.source.size=48"});
  Image ref = render_with(s, "reference");
  double hybrid = psnr(ref, render_with(s, "zslab-hybrid"));
  double full = psnr(ref, render_with(s, "zslab"));
  double mdvr = psnr(ref, render_with(s, "mdvr"));
  EXPECT_GE(hybrid, 35.0);
  EXPECT_GE(full, 35.0);
  EXPECT_GE(hybrid, mdvr - 1.0);
}

TEST(ZslabRender, MprPlanesThroughAVolume) {
  Scene s = small("mpr", {"objects.ct.source.size=48"});
  Image ref = render_with(s, "reference");
  EXPECT_GE(psnr(ref, render_with(s, "zslab-hybrid")), psnr(ref, render_with(s, "mdvr")) - 0.5);
}

TEST(ZslabRender, Rgba8SlabsStayClose) {
  Scene s = small("ct-implant", {"objects.ct.source.size=48"});
  Image f32 = render_with(s, "zslab");
  s.render.slab_format = "rgba8";
  EXPECT_GE(psnr(f32, render_with(s, "zslab")), 35.0);
}

TEST(ZslabRender, StagedEqualsStreamedAndReusesStages) {
  Scene s = small("fusion", {"objects.ct.source.size=40", "objects.pet.source.size=40"});
  Renderer r;
  RenderOptions o;
  o.method = "zslab-hybrid";
  Image first = r.render(s, o);
  EXPECT_EQ(r.last_stats().stages, 3);  // the sphere, then the two volumes
  EXPECT_EQ(r.last_stats().stages_run, 3);
  EXPECT_EQ(psnr(first, render_with(s, "zslab-hybrid")), INFINITY);

  // a TF edit of the volume cast last re-runs that stage only; which one it is, the cache says
  for (size_t v = 0; v < s.volumes.size(); ++v) {
    Scene edited = s;
    edited.volumes[v].transfer_function.points.back().rgba.a *= 0.5f;
    Image again = r.render(edited, o);
    int run = r.last_stats().stages_run;
    EXPECT_TRUE(run == 1 || run == 2) << "volume " << v;
    EXPECT_EQ(psnr(again, render_with(edited, "zslab-hybrid")), INFINITY);
    r.render(s, o);  // back to the original
  }
  Image same = r.render(s, o);
  EXPECT_EQ(r.last_stats().stages_run, 0);
  EXPECT_EQ(psnr(same, first), INFINITY);

  // object-level reuse: the sphere's own stage, and the on-the-fly cast after it
  Scene material = s;
  material.meshes[0].material.opacity = 0.8f;
  r.render(material, o);
  EXPECT_EQ(r.last_stats().stages_run, 2);
}

Scene two_volumes(std::vector<std::string> extra = {}) {
  extra.push_back("objects.cube.source.size=32");
  extra.push_back("objects.ellipsoid.source.size=32");
  return small("two-volumes", extra);
}

Scene shells_volumes(std::vector<std::string> extra = {}) {
  extra.push_back("objects.shells.source.size=48");
  extra.push_back("objects.blob.source.size=48");
  return small("shells-volumes", extra);
}

// The name of the volume the automatic choice renders last, and the other one of the two.
std::pair<std::string, std::string> automatic_last(const Scene& s) {
  ZslabFrame z(s, 1, true);
  std::string last = z.stages.back().name;
  return {last, last == s.volumes[0].name ? s.volumes[1].name : s.volumes[0].name};
}

// two-volumes with its opaque material (0.95/mm) made 0.1/mm: the kernel is symmetric in its
// inputs, so the order shows only where slabs fold or ERT cuts one volume short, which opaque
// volumes that stop within a few slabs never reach at N = 8
Scene transparent_two_volumes() {
  std::vector<std::string> extra;
  for (const char* v : {"cube", "ellipsoid"})
    for (int i : {2, 3})
      extra.push_back(fmt::format("objects.{}.transfer_function.points.{}.4=0.1", v, i));
  return two_volumes(extra);
}

// Whether the marcher finds anything on the centre ray of pixel (x, y) in volume stage k.
bool marches_something(const ZslabFrame& z, size_t k, int x, int y) {
  return test::marcher_finds_something(z.frame.volumes[static_cast<size_t>(z.stages[k].volume)],
                                       z.frame.camera.ray(x + 0.5, y + 0.5), z.stages[k].step,
                                       z.frame.lights);
}

// A volume stage leaves out the samples of pixels that no occupied brick of its volume reaches
// (BrickCoverage; that it leaves pixels out is tested there), but never one whose ray the marcher
// finds anything on: checked pixel by pixel on a wide and a tall image, where swapping x and y
// would leave out the wrong pixels, in the deferred stages of zslab and in the on-the-fly stage
// of the hybrid.
TEST(ZslabRender, VolumeStagesLeaveOutOnlyRaysWithNothingToMarch) {
  for (const char* size : {"image.width=64", "image.height=64"}) {
    const Scene s = two_volumes({size, "camera.target=[20,-20,20]"});
    const ZslabFrame z(s, 1, false), hybrid(s, 1, true);
    const size_t last = hybrid.stages.size() - 1;
    ASSERT_TRUE(hybrid.stages[last].on_the_fly);
    int marched = 0;
    for (int y = 0; y < s.image.height; ++y)
      for (int x = 0; x < s.image.width; ++x) {
        const Ray ray = z.frame.camera.ray(x + 0.5, y + 0.5);
        for (size_t k = 0; k < z.stages.size(); ++k) {
          if (z.stages[k].kind != ZslabStage::Kind::volume) continue;
          Slab slots[kMaxZslabLayers];
          SlabList out(std::span<Slab>(slots, static_cast<size_t>(z.params.layers)));
          const bool ran = z.run_deferred(k, x, y, ray, {}, {}, out);
          if (marches_something(z, k, x, y)) {
            EXPECT_TRUE(ran) << size << " stage " << k << " pixel " << x << ", " << y;
            ++marched;
          }
        }
        if (marches_something(hybrid, last, x, y)) {
          EXPECT_GT(hybrid.run_final(last, x, y, ray, {}).a, 0.0f)
              << size << " on the fly, pixel " << x << ", " << y;
        }
      }
    EXPECT_GT(marched, 500) << size;
  }
}

TEST(ZslabRender, LastVolumeSettingChoosesTheLastStage) {
  Scene s = transparent_two_volumes();
  auto [chosen, other] = automatic_last(s);
  Scene swapped = s;
  swapped.render.last_volume = other;
  for (bool hybrid : {false, true}) {
    ZslabFrame z(swapped, 1, hybrid);
    ASSERT_EQ(z.stages.size(), 2u);
    EXPECT_EQ(z.stages[0].name, chosen);
    EXPECT_FALSE(z.stages[0].on_the_fly);
    EXPECT_EQ(z.stages[1].name, other);
    EXPECT_EQ(z.stages[1].on_the_fly, hybrid);
  }

  Image ref = render_with(s, "reference");
  Image automatic = render_with(s, "zslab-hybrid");
  Image reordered = render_with(swapped, "zslab-hybrid");
  EXPECT_LT(psnr(automatic, reordered), 75.0) << "the order made no difference";
  EXPECT_GE(psnr(ref, reordered), 35.0);
  Scene named = s;  // naming the automatic choice changes nothing
  named.render.last_volume = chosen;
  EXPECT_EQ(psnr(automatic, render_with(named, "zslab-hybrid")), INFINITY);
}

TEST(ZslabRender, LastVolumeMattersWithTransparentVolumes) {
  Scene s = shells_volumes();
  auto [chosen, other] = automatic_last(s);
  Scene swapped = shells_volumes({"render.last_volume=" + other});
  ASSERT_EQ(swapped.render.last_volume, other);
  Image automatic = render_with(s, "zslab-hybrid");
  Image reordered = render_with(swapped, "zslab-hybrid");
  EXPECT_LT(psnr(automatic, reordered), 70.0);
  Image ref = render_with(s, "reference");
  EXPECT_GE(psnr(ref, reordered), 35.0);
}

TEST(ZslabRender, LastVolumeMustBeAVolumeOfTheScene) {
  Scene s = two_volumes();
  s.render.last_volume = "sphere";  // a scene built in code skips the parser's check
  try {
    render_with(s, "zslab-hybrid");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find("last_volume"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'sphere'"), std::string::npos) << msg;
  }
}

TEST(ZslabRender, ChangingTheLastVolumeReRunsTheReorderedStages) {
  Scene s = shells_volumes();
  auto [chosen, other] = automatic_last(s);
  Renderer r;
  RenderOptions o;
  o.method = "zslab-hybrid";
  Image first = r.render(s, o);
  Scene swapped = s;
  swapped.render.last_volume = other;
  Image again = r.render(swapped, o);
  EXPECT_EQ(r.last_stats().stages_run, 2);  // the order changed the first stage too
  EXPECT_EQ(psnr(again, render_with(swapped, "zslab-hybrid")), INFINITY);
  EXPECT_LT(psnr(again, first), INFINITY);
  EXPECT_EQ(psnr(r.render(s, o), first), INFINITY);
  Scene named = s;
  named.render.last_volume = chosen;  // the same order: everything is reused
  EXPECT_EQ(psnr(r.render(named, o), first), INFINITY);
  EXPECT_EQ(r.last_stats().stages_run, 0);
}

// shells-volumes at N = 4: the transparent shells give far more slabs than fit.
Scene many_slabs(const std::string& overflow) {
  return shells_volumes({"render.layers=4", "render.overflow=" + overflow});
}

TEST(ZslabRender, OverflowTailDiffersFromGreedy) {
  Scene greedy = many_slabs("greedy"), tail = many_slabs("tail");
  ASSERT_EQ(tail.render.overflow, "tail");
  Image ref = render_with(greedy, "reference");
  for (const char* method : {"zslab", "zslab-hybrid"}) {
    Image g = render_with(greedy, method);
    Image t = render_with(tail, method);
    EXPECT_LT(psnr(g, t), 60.0) << method << ": the policy made no difference";
    EXPECT_GE(psnr(ref, t), 25.0) << method;
    EXPECT_EQ(psnr(g, render_with(many_slabs("greedy"), method)), INFINITY);
  }

  // the policy is part of every stage's key: no output kept under greedy is reused for tail
  // (a copy, so the volumes keep their identity, which the keys hash)
  Scene edited = greedy;
  edited.render.overflow = "tail";
  Renderer r;
  RenderOptions o;
  o.method = "zslab";
  r.render(greedy, o);
  Image again = r.render(edited, o);
  EXPECT_EQ(r.last_stats().stages_run, r.last_stats().stages);
  EXPECT_EQ(psnr(again, render_with(edited, "zslab")), INFINITY);
}

TEST(ZslabRender, OverflowTailNeverExceedsTheCapacity) {
  for (const char* policy : {"tail", "greedy"}) {
    Scene s = many_slabs(policy);
    ZslabFrame z(s, 1, false);
    ASSERT_EQ(z.params.mix.overflow,
              std::string(policy) == "tail" ? Overflow::tail : Overflow::greedy);
    const int n = z.params.layers;
    ASSERT_EQ(n, 4);
    const Slab sentinel{-1.0f, -7.0f, glm::vec4(9.0f)};
    int full = 0;
    for (int y = 0; y < kSize; y += 2)
      for (int x = 0; x < kSize; x += 2) {
        Ray ray = z.frame.camera.ray(x + 0.5, y + 0.5);
        std::vector<Slab> stored;
        for (size_t k = 0; k < z.stages.size(); ++k) {
          std::vector<Slab> slots(n + 4, sentinel);
          SlabList out(std::span<Slab>(slots.data(), static_cast<size_t>(n)));
          if (!z.run_deferred(k, x, y, ray, {}, stored, out)) continue;
          ASSERT_LE(out.size(), n);
          for (int i = n; i < n + 4; ++i) ASSERT_EQ(slots[i].color, sentinel.color);
          for (int i = 1; i < out.size(); ++i) ASSERT_GE(out[i].front(), out[i - 1].t_back - 1e-3f);
          stored.assign(out.begin(), out.end());
          full += out.size() == n;
        }
      }
    EXPECT_GT(full, 50) << policy << ": too few samples filled the array to test overflow";
  }
}

TEST(ZslabRender, MemoryPerPixelWithinBound) {
  Scene s = small("fusion", {"objects.ct.source.size=32", "objects.pet.source.size=32"});
  for (int n : {4, 8, 16})
    for (const char* format : {"rgba32f", "rgba8"}) {
      s.render.layers = n;
      s.render.slab_format = format;
      double slab = std::string(format) == "rgba8" ? 12.0 : 24.0;
      double bound = (2.0 * n + s.render.rt_layers) * slab;
      // kept own arrays at full precision with a count: N slots a volume, L the sphere
      double kept = 2 * (24.0 * n + 1.0) + 24.0 * s.render.peel_layers + 1.0;
      Renderer r;
      RenderOptions o;
      o.method = "zslab";
      r.render(s, o);
      EXPECT_LE(r.last_stats().kept_bytes_per_pixel, kept) << n << " " << format;
      EXPECT_GT(r.last_stats().kept_bytes_per_pixel, 0.0);
      EXPECT_LE(zslab_stream_bytes_per_sample(s.render), bound + 1.0);
    }
}

}  // namespace
}  // namespace imx

namespace imx {
namespace {

// A surface stage skips the tiles outside its objects' screen rectangle: every pixel holding one
// of its fragments must lie inside it (a rectangle a pixel too small, or a box corner behind the
// eye taken as bounded, fails this). Seen from afar, and with the eye among the objects.
TEST(ZslabStages, ScreenRectanglesHoldEveryFragment) {
  constexpr int kW = 96, kH = 72;
  for (const std::string& camera :
       {std::string("camera.target=[0,0,0]"), std::string("camera.eye=[5,-8,3]")}) {
    Scene s = load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "torus-planes.json",
                         {"image.width=96", "image.height=72", camera});
    ZslabFrame z(s, 1, true);
    z.prepare();
    int bounded = 0;
    for (size_t k = 0; k < z.stages.size(); ++k) {
      const ZslabStage& st = z.stages[k];
      if (st.kind != ZslabStage::Kind::surfaces) continue;
      bounded += st.x1 - st.x0 < kW || st.y1 - st.y0 < kH;
      for (int y0 = 0; y0 < kH; y0 += 16)  // the rasterizer's 16-pixel tiles
        for (int x0 = 0; x0 < kW; x0 += 16) {
          const TileRect tile{x0, y0, std::min(x0 + 16, kW), std::min(y0 + 16, kH)};
          SampleFragments f;
          z.rasterize(k, tile, f);
          for (size_t i = 0; i < f.sample_count(); ++i) {
            if (f.of(i).empty()) continue;
            const int x = tile.x0 + static_cast<int>(i) % tile.width();
            const int y = tile.y0 + static_cast<int>(i) / tile.width();
            ASSERT_TRUE(x >= st.x0 && x < st.x1 && y >= st.y0 && y < st.y1)
                << camera << ": stage " << st.name << " pixel " << x << "," << y;
            EXPECT_TRUE(z.stage_reaches(k, tile));
          }
        }
    }
    EXPECT_GT(bounded, 10) << camera;  // the rectangles do leave pixels out
  }
}

}  // namespace
}  // namespace imx
