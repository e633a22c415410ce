// imx::Renderer's object-level reuse for zslab and zslab-hybrid (SPEC §4): after an edit of any
// one object only that object is rendered again, the image equals a fresh render of the edited
// scene byte for byte, and the kept arrays stay within the memory budget.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "intermix/render.hpp"
#include "intermix/renderer.hpp"
#include "intermix/scene.hpp"
#include "methods/zslab/zslab_frame.hpp"
#include "same_image.hpp"

namespace imx {
namespace {

constexpr int kSize = 40;

Scene small(const std::string& name, std::vector<std::string> extra = {}) {
  extra.push_back("image.width=" + std::to_string(kSize));
  extra.push_back("image.height=" + std::to_string(kSize + 8));  // not square: x, y not swapped
  return load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / (name + ".json"), extra);
}

// The three kinds of scene the brief names: planes through a volume, two volumes and a mesh,
// meshes in a volume. The last volume is named, so a TF edit does not reorder the stages.
Scene mpr() {
  return small("mpr", {"objects.ct.source.size=40"});
}
Scene fusion() {
  return small("fusion", {"objects.ct.source.size=36", "objects.pet.source.size=36",
                          "render.last_volume=pet"});
}
Scene fusion_rgba8() {  // stage outputs rounded to 8 bits, own arrays kept at full precision
  Scene s = fusion();
  s.render.slab_format = "rgba8";
  return s;
}
Scene implant() {
  return small("ct-implant", {"objects.ct.source.size=40"});
}

Image fresh(const Scene& s, const std::string& method) {
  RenderOptions o;
  o.method = method;
  return render(s, o);
}

using test::same_bytes;

// One edit of one object: its Scene::order index and the edited scene.
struct Edit {
  std::string what;
  size_t order = 0;
  Scene scene;
};

// An edit of every object in turn, each of what an interactive viewer changes: a volume's TF, a
// plane's window/level, a mesh's colour and opacity.
std::vector<Edit> edits_of(const Scene& s) {
  std::vector<Edit> out;
  for (size_t k = 0; k < s.order.size(); ++k) {
    const ObjectRef& ref = s.order[k];
    Edit e{"", k, s};
    if (ref.kind == ObjectKind::volume) {
      e.what = "tf of " + s.volumes[ref.index].name;
      for (TfPoint& p : e.scene.volumes[ref.index].transfer_function.points) p.rgba.a *= 0.6f;
    } else if (ref.kind == ObjectKind::plane) {
      e.what = "window of " + s.planes[ref.index].name;
      e.scene.planes[ref.index].window += glm::vec2(60.0f, -80.0f);
    } else if (ref.kind == ObjectKind::mesh) {
      e.what = "material of " + s.meshes[ref.index].name;
      e.scene.meshes[ref.index].material.color = {0.9f, 0.2f, 0.6f};
      e.scene.meshes[ref.index].material.opacity = 0.8f;
    }
    out.push_back(std::move(e));
  }
  return out;
}

// The stage that renders Scene::order entry `order`.
const ZslabStage& stage_of(const ZslabFrame& z, size_t order) {
  for (const ZslabStage& st : z.stages)
    for (uint32_t o : st.objects)
      if (o == order) return st;
  throw std::runtime_error("no stage renders it");
}

struct Case {
  const char* name;
  Scene (*make)();
};
const Case kCases[] = {
    {"mpr", mpr}, {"fusion", fusion}, {"fusion-rgba8", fusion_rgba8}, {"ct-implant", implant}};

// Edit each object in turn, then go back: each frame equals a fresh render, only the edited
// object's stage ran (and, in zslab-hybrid, the on-the-fly cast of the last volume).
TEST(RendererReuse, EachEditRendersOnlyItsObjectAndEqualsAFreshFrame) {
  for (const Case& c : kCases)
    for (const char* method : {"zslab", "zslab-hybrid"}) {
      const Scene base = c.make();
      const bool hybrid = std::string(method) == "zslab-hybrid";
      RenderOptions o;
      o.method = method;
      Renderer r;
      const Image first = r.render(base, o);
      ASSERT_TRUE(same_bytes(first, fresh(base, method))) << c.name << " " << method;
      ASSERT_EQ(r.last_stats().stages_run, r.last_stats().stages);
      ASSERT_GE(r.last_stats().stages, 3) << c.name;
      for (const Edit& e : edits_of(base)) {
        const ZslabFrame z(e.scene, 1, hybrid);
        const ZslabStage& st = stage_of(z, e.order);
        const int expected = hybrid && !st.on_the_fly && z.stages.back().on_the_fly ? 2 : 1;
        for (int round = 0; round < 2; ++round) {  // the second round finds the merged prefix
          const Image edited = r.render(e.scene, o);
          EXPECT_TRUE(same_bytes(edited, fresh(e.scene, method)))
              << c.name << " " << method << " " << e.what << " round " << round;
          EXPECT_EQ(r.last_stats().stages_run, expected)
              << c.name << " " << method << " " << e.what;
          EXPECT_EQ(r.last_stats().recast_unchanged, expected == 2) << c.name << " " << e.what;
          EXPECT_FALSE(same_bytes(edited, first)) << c.name << " " << e.what << ": no change";
          const Image back = r.render(base, o);
          EXPECT_TRUE(same_bytes(back, first)) << c.name << " " << method << " " << e.what;
          EXPECT_EQ(r.last_stats().stages_run, expected) << c.name << " " << e.what;
        }
      }
      r.render(base, o);
      EXPECT_EQ(r.last_stats().stages_run, 0) << c.name << " " << method;
    }
}

// An edit of the last deferred object, repeated as a viewer's drag does, merges from the kept
// prefix: only its own stage's merge runs, not those of the stages before it.
TEST(RendererReuse, EditOfTheLastObjectMergesOnlyItsOwnStage) {
  for (const char* method : {"zslab", "zslab-hybrid"}) {
    const Scene base = fusion();
    const bool hybrid = std::string(method) == "zslab-hybrid";
    const ZslabFrame z(base, 1, hybrid);
    const size_t last = z.stages.size() - 1;  // the pet: deferred (zslab) or on the fly
    ASSERT_EQ(z.stages[last].name, "pet");
    RenderOptions o;
    o.method = method;
    Renderer r;
    r.render(base, o);
    Scene edited = base;
    for (TfPoint& p : edited.volumes[1].transfer_function.points) p.rgba.g *= 0.5f;
    for (int round = 0; round < 3; ++round) {
      const Image a = r.render(edited, o);
      EXPECT_TRUE(same_bytes(a, fresh(edited, method))) << method << " round " << round;
      EXPECT_EQ(r.last_stats().stages_run, 1) << method;
      if (round > 0) {
        EXPECT_EQ(r.last_stats().stages_merged, hybrid ? 0 : 1) << method;
      }
      r.render(base, o);
    }
  }
}

// A budget too small for every array evicts the largest first; what is evicted is rendered
// again each frame, the bytes stay within the budget, and the image is still exact.
TEST(RendererReuse, TinyBudgetEvictsLargestFirstAndStaysExact) {
  for (const Case& c : kCases) {
    const Scene base = c.make();
    const ZslabFrame z(base, 1, false);
    const double samples = static_cast<double>(base.image.width) * base.image.height;
    // room for one N-slab array and a bit: the surface arrays stay, the volume ones go
    const uint64_t budget = static_cast<uint64_t>(samples * (24.0 * z.params.layers + 1.0)) + 1000;
    for (uint64_t b : {budget, uint64_t{0}}) {
      Renderer r;
      r.set_kept_budget(b);
      RenderOptions o;
      o.method = "zslab";
      r.render(base, o);
      EXPECT_LE(r.last_stats().kept_bytes_per_pixel * samples, static_cast<double>(b)) << c.name;
      for (const Edit& e : edits_of(base)) {
        EXPECT_TRUE(same_bytes(r.render(e.scene, o), fresh(e.scene, "zslab")))
            << c.name << " budget " << b << " " << e.what;
        EXPECT_LE(r.last_stats().kept_bytes_per_pixel * samples, static_cast<double>(b));
        const int volumes = static_cast<int>(base.volumes.size());
        const bool volume_edit = base.order[e.order].kind == ObjectKind::volume;
        // every volume's array was evicted: each volume is cast again
        EXPECT_GE(r.last_stats().stages_run, volumes + (volume_edit ? 0 : 1))
            << c.name << " " << e.what;
        if (b == 0) {
          EXPECT_EQ(r.last_stats().kept_bytes_per_pixel, 0.0);
        } else {
          EXPECT_GT(r.last_stats().kept_bytes_per_pixel, 0.0) << c.name;
        }
      }
    }
  }
}

// The kept arrays per pixel are those the design describes: own arrays (24 B a slot: N for a
// volume, 1 for a plane, L for a mesh) plus at most one merged N-slab array, each with a count.
TEST(RendererReuse, KeptBytesPerPixelAsDocumented) {
  const Scene s = mpr();  // three planes and one volume
  RenderOptions o;
  o.method = "zslab";
  Renderer r;
  r.render(s, o);
  const double n = s.render.layers;
  const double own = 3 * (24.0 + 1.0) + (24.0 * n + 1.0);
  EXPECT_DOUBLE_EQ(r.last_stats().kept_bytes_per_pixel, own);
  Scene edited = s;
  edited.planes[1].window.y *= 2.0f;  // the coronal plane, stage 1 of 4: no prefix (one merge)
  r.render(edited, o);
  EXPECT_DOUBLE_EQ(r.last_stats().kept_bytes_per_pixel, own);
  edited.planes[2].window.y *= 2.0f;  // sagittal, stage 2: the prefix of two stages pays
  r.render(edited, o);
  EXPECT_DOUBLE_EQ(r.last_stats().kept_bytes_per_pixel, own + 24.0 * n + 1.0);
}

// Switching between the two zslab methods keeps both methods' arrays (a viewer may render edits
// with zslab and the settled frame with zslab-hybrid), within one budget.
TEST(RendererReuse, BothMethodsKeepTheirArrays) {
  const Scene s = fusion();
  Renderer r;
  RenderOptions full, hybrid;
  full.method = "zslab";
  hybrid.method = "zslab-hybrid";
  r.render(s, full);
  r.render(s, hybrid);
  EXPECT_TRUE(same_bytes(r.render(s, full), fresh(s, "zslab")));
  EXPECT_EQ(r.last_stats().stages_run, 0);
  EXPECT_TRUE(same_bytes(r.render(s, hybrid), fresh(s, "zslab-hybrid")));
  EXPECT_EQ(r.last_stats().stages_run, 0);
}

// The kept path gives the same bytes whatever the thread count.
TEST(RendererReuse, SameBytesForAnyThreadCount) {
  const Scene s = fusion();
  Scene edited = s;
  edited.volumes[0].transfer_function.points.back().rgba.a *= 0.5f;
  for (const char* method : {"zslab", "zslab-hybrid"}) {
    Image images[2];
    for (int t : {1, 3}) {
      RenderOptions o;
      o.method = method;
      o.threads = t;
      Renderer r;
      r.render(s, o);
      images[t == 3] = r.render(edited, o);
    }
    EXPECT_TRUE(same_bytes(images[0], images[1])) << method;
  }
}

}  // namespace
}  // namespace imx
