// The images are untouched: every example and bench scene, rendered small with every method
// that takes it, hashes to the bytes recorded in tests/golden/hashes/. A refactor that moves
// code must leave every hash as it was; a change that means to alter images records new hashes
// (IMX_UPDATE_IMAGE_HASHES=1 ctest -R ImageHashes) and says why in its commit.
// The bytes depend on the compiler and its flags, so the hashes hold for the build that
// recorded them (the first line of each file) and the test skips in any other. They depend on
// the SIMD target the lane kernels run on only where its arithmetic differs (kTargetTolerance):
// `method hash` is the widest target's, `method@TARGET hash` another target's that differs.
// The test checks the target the kernels run on (IMX_SIMD=lowest: the portable one); a
// recording renders every target this machine runs and checks each one's tolerance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/fnv1a.hpp"
#include "each_simd_target.hpp"
#include "intermix/error.hpp"
#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/renderer.hpp"
#include "intermix/scene.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;

struct SceneFile {
  std::string group;  // examples or bench
  fs::path path;
};

std::vector<SceneFile> scene_files() {
  std::vector<SceneFile> files;
  for (const auto& [group, dir] : {std::pair{"examples", fs::path(IMX_EXAMPLES_DIR)},
                                   std::pair{"bench", fs::path(IMX_BENCH_SCENES_DIR)}})
    for (const fs::directory_entry& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".json") files.push_back({group, e.path()});
  std::sort(files.begin(), files.end(),
            [](const SceneFile& a, const SceneFile& b) { return a.path < b.path; });
  return files;
}

std::string label(const SceneFile& f) {
  return f.group + "-" + f.path.stem().string();
}

// ctest's listing names the scene, not the parameter's bytes.
void PrintTo(const SceneFile& f, std::ostream* out) {
  *out << label(f);
}

fs::path hash_file(const SceneFile& f) {
  return fs::path(IMX_GOLDEN_DIR) / "hashes" / (label(f) + ".txt");
}

std::string image_hash(const Image& image) {
  return fmt::format("{:016x}", Fnv1a()
                                    .add(image.width())
                                    .add(image.height())
                                    .add_bytes(image.data(), image.size() * sizeof(glm::vec4))
                                    .value());
}

// How far a target's images may lie from the widest target's, and why. Targets with FMA (AVX2,
// AVX-512, NEON) compute every lane as the widest does, so their bytes must not differ; SSE4 and
// the portable targets round a multiply-add twice, which moves a sample by an ulp or so: no
// pixel of the 48x40 images may move by more than 1/255 and the image must stay within
// kMinPsnr of the widest's.
bool exact_target(const std::string& target) {
  return target == "AVX3" || target == "AVX3_DL" || target == "AVX2" || target == "NEON";
}
constexpr float kMaxPixelDifference = 1.0f / 255.0f;
constexpr double kMinPsnr = 60.0;

// Every method's image of the scene ("refused" methods hold none). The zslab methods also render
// through a Renderer twice (the second frame reuses every stage), and those frames must hash as
// render()'s.
std::map<std::string, std::optional<Image>> render_every_method(const Scene& scene) {
  std::map<std::string, std::optional<Image>> images;
  for (const std::string& method : available_methods()) {
    RenderOptions options;
    options.method = method;
    try {
      Image image = render(scene, options);
      const std::string hash = image_hash(image);
      if (method.starts_with("zslab")) {
        Renderer renderer;
        const std::string first = image_hash(renderer.render(scene, options));
        const std::string reused = image_hash(renderer.render(scene, options));
        EXPECT_EQ(first, hash) << method << ": Renderer's first frame";
        EXPECT_EQ(reused, hash) << method << ": Renderer's frame of kept stages";
      }
      images[method] = std::move(image);
    } catch (const Error&) {
      images[method] = std::nullopt;
    }
  }
  return images;
}

std::string hash_of(const std::optional<Image>& image) {
  return image ? image_hash(*image) : "refused";
}

// Records the hashes of every target this machine runs: the widest's, and each other target's
// that differs, once its images are checked against the tolerance.
void record(const fs::path& path, const Scene& scene, const std::string& build) {
  std::map<std::string, std::optional<Image>> widest;
  std::map<std::string, std::string> lines;
  test::for_each_simd_target([&](const std::string& target) {
    std::map<std::string, std::optional<Image>> images = render_every_method(scene);
    if (widest.empty()) {
      for (const auto& [method, image] : images) lines[method] = hash_of(image);
      widest = std::move(images);
      return;
    }
    for (const auto& [method, image] : images) {
      if (hash_of(image) == lines.at(method)) continue;
      EXPECT_FALSE(exact_target(target)) << method << " differs on " << target;
      ASSERT_TRUE(image && widest.at(method)) << method << ": refused on one target only";
      const ImageComparison d = compare_images(*widest.at(method), *image);
      EXPECT_LE(d.max_error, kMaxPixelDifference) << method << " on " << target;
      EXPECT_GE(d.psnr_db, kMinPsnr) << method << " on " << target;
      lines[method + "@" + target] = hash_of(image);
    }
  });
  fs::create_directories(path.parent_path());
  std::ofstream out(path);
  out << "# " << build << "\n";
  for (const auto& [method, hash] : lines) out << method << " " << hash << "\n";
}

class ImageHashes : public testing::TestWithParam<SceneFile> {};

TEST_P(ImageHashes, EveryMethodRendersTheRecordedBytes) {
  const SceneFile& file = GetParam();
  Scene scene;
  try {
    // Small and not square (a transposed image hashes differently); the scene's own samples.
    scene = load_scene(file.path, {"image.width=48", "image.height=40"});
  } catch (const FileError& e) {
    GTEST_SKIP() << "its data is not here: " << e.what();  // ../shared/data absent
  }
  const std::string build = IMX_IMAGE_HASH_BUILD;
  const bool update = std::getenv("IMX_UPDATE_IMAGE_HASHES") != nullptr;
  std::ifstream in;
  std::string first_line;
  if (!update) {
    in.open(hash_file(file));
    ASSERT_TRUE(in) << hash_file(file) << " is missing: record it with IMX_UPDATE_IMAGE_HASHES=1";
    std::getline(in, first_line);
    // Before rendering: another build's bytes say nothing here (the sanitizer build spent about
    // 45 s a scene rendering images it then skipped).
    ASSERT_TRUE(first_line.starts_with("# "))
        << hash_file(file) << ": the first line names no build: record it again";
    if (first_line != "# " + build)
      GTEST_SKIP() << "hashes recorded by '" << first_line.substr(2) << "', this is '" << build
                   << "'";
  }
  if (update) {
    record(hash_file(file), scene, build);
    return;
  }
  std::map<std::string, std::string> recorded;
  for (std::string method, hash; in >> method >> hash;) recorded[method] = hash;
  const std::string target = simd_target();
  size_t methods = 0;
  for (const auto& [method, image] : render_every_method(scene)) {
    ++methods;
    const std::string own = method + "@" + target;
    const std::string key = recorded.contains(own) ? own : method;
    ASSERT_TRUE(recorded.contains(key)) << method << " has no recorded hash";
    EXPECT_EQ(hash_of(image), recorded.at(key)) << key << " on " << file.path.filename();
  }
  const auto widest_lines = std::count_if(recorded.begin(), recorded.end(), [](const auto& line) {
    return line.first.find('@') == std::string::npos;
  });
  EXPECT_EQ(static_cast<size_t>(widest_lines), methods)
      << "a recorded method is no longer available";
}

INSTANTIATE_TEST_SUITE_P(EveryScene, ImageHashes, testing::ValuesIn(scene_files()),
                         [](const testing::TestParamInfo<SceneFile>& info) {
                           std::string name = label(info.param);
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

}  // namespace
}  // namespace imx
