// zslab and zslab-hybrid on small example scenes: quality against the reference, the streamed
// and the staged pipelines agreeing, stage reuse after an edit, and the memory bound.
#include <gtest/gtest.h>

#include <filesystem>

#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/renderer.hpp"
#include "intermix/scene.hpp"
#include "methods/zslab.hpp"

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

  Scene material = s;
  material.meshes[0].material.opacity = 0.8f;
  r.render(material, o);
  EXPECT_EQ(r.last_stats().stages_run, 3);
}

TEST(ZslabRender, MemoryPerPixelWithinBound) {
  Scene s = small("fusion", {"objects.ct.source.size=32", "objects.pet.source.size=32"});
  for (int n : {4, 8, 16})
    for (const char* format : {"rgba32f", "rgba8"}) {
      s.render.layers = n;
      s.render.slab_format = format;
      double slab = std::string(format) == "rgba8" ? 12.0 : 24.0;
      double bound = (2.0 * n + s.render.rt_layers) * slab;
      Renderer r;
      RenderOptions o;
      o.method = "zslab";
      r.render(s, o);
      EXPECT_LE(r.last_stats().kept_bytes_per_pixel, bound) << n << " " << format;
      EXPECT_GT(r.last_stats().kept_bytes_per_pixel, 0.0);
      EXPECT_LE(zslab_stream_bytes_per_sample(s.render), bound + 1.0);
    }
}

}  // namespace
}  // namespace imx
