// Determinism (DESIGN principle 4): every method gives byte-identical images whatever the
// thread count. Small example scenes with volumes, meshes, MPR planes and clip planes, and a
// CSG scene for the methods that render CSG, each at 1, 2 and 3 threads.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <tbb/global_control.h>

#include "intermix/error.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx {
namespace {

struct ExampleScene {
  const char* file;
  std::vector<std::string> overrides;  // beyond the image size: smaller phantoms, fewer triangles
};

// Volumes AND meshes in every scene, so the multi-fragment methods have layers to sort, merge
// and mix: a clipped CT with an MPR plane, a transparent plane and two quads; CT + PET fusion
// with a transparent sphere; coplanar quads (z-fighting, jittered samples) in a volume; a CSG
// cut of two volumes by a ball; exclusive CSG mixing.
const std::vector<ExampleScene>& scenes() {
  static const std::vector<ExampleScene> list = {
      {"mpr-widgets", {"objects.ct.source.size=64"}},
      {"fusion", {"objects.ct.source.size=48", "objects.pet.source.size=32"}},
      {"coplanar", {"objects.ball.source.size=32"}},
      {"csg-cutaway",
       {"objects.skin.source.size=48", "objects.bone.source.size=48",
        "objects.ball.source.segments=24"}},
      {"csg-mixing",
       {"objects.skin.source.size=48", "objects.bone.source.size=48",
        "objects.ball.source.segments=24"}},
  };
  return list;
}

Scene load_example(const ExampleScene& example) {
  std::vector<std::string> overrides = example.overrides;
  overrides.push_back("image.width=64");
  overrides.push_back("image.height=48");
  return load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / (std::string(example.file) + ".json"),
                    overrides);
}

// Empty when the images are byte-identical, else where and how they first differ.
std::string difference(const Image& a, const Image& b) {
  if (a.width() != b.width() || a.height() != b.height())
    return fmt::format("sizes differ: {}x{} vs {}x{}", a.width(), a.height(), b.width(),
                       b.height());
  int differing = 0, first_x = -1, first_y = -1;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      if (std::memcmp(&a.at(x, y), &b.at(x, y), sizeof(glm::vec4)) != 0 && differing++ == 0) {
        first_x = x;
        first_y = y;
      }
  if (differing == 0) return {};
  const glm::vec4 p = a.at(first_x, first_y), q = b.at(first_x, first_y);
  return fmt::format("{} pixels differ; first at ({}, {}): ({}, {}, {}, {}) vs ({}, {}, {}, {})",
                     differing, first_x, first_y, p.r, p.g, p.b, p.a, q.r, q.g, q.b, q.a);
}

// Pixels that differ from the top-left one: the scene must show something at this size.
int non_background_pixels(const Image& image) {
  int n = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      n += std::memcmp(&image.at(x, y), &image.at(0, 0), sizeof(glm::vec4)) != 0;
  return n;
}

class Determinism : public testing::TestWithParam<std::string> {};

TEST_P(Determinism, ImagesAreByteIdenticalAtOneTwoAndThreeThreads) {
  const std::string& method = GetParam();
  const bool renders_csg = method == "reference" || method == "csg";
  // TBB caps its workers at the core count less one: lift the cap, so that 3 threads are 3 on a
  // two-core machine too.
  tbb::global_control workers(tbb::global_control::max_allowed_parallelism, 4);
  int rendered = 0;
  for (const ExampleScene& example : scenes()) {
    std::vector<Image> images;
    bool refused = false;
    for (int threads : {1, 2, 3}) {
      // A fresh scene each time: the per-volume acceleration caches (brick min/max, gradients)
      // live as long as the voxel arrays, so each thread count builds its own.
      Scene scene = load_example(example);
      RenderOptions options;
      options.method = method;
      options.spp = 4;  // several samples per pixel: per-pixel seeds and sample patterns too
      options.threads = threads;
      try {
        images.push_back(render(scene, options));
      } catch (const Error& e) {
        // Only CSG or exclusive-mixing scenes may be refused, and only by the other methods.
        ASSERT_TRUE(scene.csg || scene.render.mixing == "exclusive")
            << method << " refused " << example.file << ": " << e.what();
        EXPECT_FALSE(renders_csg) << method << " refused " << example.file << ": " << e.what();
        refused = true;
        break;
      }
    }
    if (refused) continue;
    ++rendered;
    EXPECT_GT(non_background_pixels(images[0]), 200) << method << " on " << example.file;
    for (int i = 1; i < 3; ++i) {
      std::string diff = difference(images[0], images[i]);
      EXPECT_TRUE(diff.empty()) << method << " on " << example.file << ": 1 thread vs " << i + 1
                                << " threads: " << diff;
    }
  }
  EXPECT_GE(rendered, 3) << method;
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, Determinism, testing::ValuesIn(available_methods()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

}  // namespace
}  // namespace imx
