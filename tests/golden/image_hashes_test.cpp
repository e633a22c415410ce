// The images are untouched: every example and bench scene, rendered small with every method
// that takes it, hashes to the bytes recorded in tests/golden/hashes/. A refactor that moves
// code must leave every hash as it was; a change that means to alter images records new hashes
// (IMX_UPDATE_IMAGE_HASHES=1 ctest -R ImageHashes) and says why in its commit.
// The bytes depend on the compiler and its flags, so the hashes hold for the build that
// recorded them (the first line of each file) and the test skips in any other.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/fnv1a.hpp"
#include "intermix/error.hpp"
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

// One line per method: its hash, or "refused" for a method that does not take the scene. The
// zslab methods also render through a Renderer twice (the second frame reuses every stage),
// and those frames must hash as render()'s.
std::map<std::string, std::string> render_every_method(const Scene& scene) {
  std::map<std::string, std::string> lines;
  for (const std::string& method : available_methods()) {
    RenderOptions options;
    options.method = method;
    try {
      const std::string hash = image_hash(render(scene, options));
      lines[method] = hash;
      if (method.starts_with("zslab")) {
        Renderer renderer;
        const std::string first = image_hash(renderer.render(scene, options));
        const std::string reused = image_hash(renderer.render(scene, options));
        EXPECT_EQ(first, hash) << method << ": Renderer's first frame";
        EXPECT_EQ(reused, hash) << method << ": Renderer's frame of kept stages";
      }
    } catch (const Error&) {
      lines[method] = "refused";
    }
  }
  return lines;
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
  const std::map<std::string, std::string> rendered = render_every_method(scene);
  if (update) {
    fs::create_directories(hash_file(file).parent_path());
    std::ofstream out(hash_file(file));
    out << "# " << build << "\n";
    for (const auto& [method, hash] : rendered) out << method << " " << hash << "\n";
    return;
  }
  std::map<std::string, std::string> recorded;
  for (std::string method, hash; in >> method >> hash;) recorded[method] = hash;
  for (const auto& [method, hash] : rendered) {
    ASSERT_TRUE(recorded.contains(method)) << method << " has no recorded hash";
    EXPECT_EQ(hash, recorded.at(method)) << method << " on " << file.path.filename();
  }
  EXPECT_EQ(recorded.size(), rendered.size()) << "a recorded method is no longer available";
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
