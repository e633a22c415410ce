// bench --write-peer-scene: what the VTK peer is given. VTK's ray caster ignores a grid's
// direction, so an oblique or flipped volume must reach it on its axes, with the camera moved into
// the volume's frame: the peer's scene must show the image the original scene shows.
#include <cmath>
#include <fstream>
#include <variant>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "intermix/io.hpp"
#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "mrtrix_tracks.hpp"
#include "temp_dir.hpp"

namespace imx::test {
namespace {

// A CT phantom with its first third along i cut away (so that a wrong mirror shows) placed by
// `index_to_world`, in a scene with a shaded bone-like TF and a fixed camera, 64 x 64.
std::filesystem::path write_scene(const TempDir& dir, const glm::dmat4& index_to_world) {
  VolumeData v = make_phantom("ct-head", 32);
  std::visit(
      [&](auto& voxels) {
        auto* values = voxels.mutable_data();
        const auto air = values[0];  // a corner
        for (size_t n = 0; n < voxels.size(); ++n)
          if (static_cast<int>(n % static_cast<size_t>(v.dims.x)) < v.dims.x / 3) values[n] = air;
      },
      v.voxels);
  v.index_to_world = index_to_world;
  write_metaimage(v, dir / "volume.mha", false);
  const glm::dvec3 centre(index_to_world * glm::dvec4(glm::dvec3(v.dims - 1) * 0.5, 1.0));
  nlohmann::json scene = {
      {"image", {{"width", 64}, {"height", 64}, {"background", {0, 0, 0}}}},
      {"camera",
       {{"eye", {centre.x + 24, centre.y - 36, centre.z + 16}},
        {"target", {centre.x, centre.y, centre.z}},
        {"up", {0, 0, 1}}}},
      {"objects",
       {{{"name", "ct"},
         {"type", "volume"},
         {"source", {{"file", (dir / "volume.mha").string()}}},
         {"transfer_function",
          {{"points",
            {{-200, 0, 0, 0, 0},
             {100, 1, 0.6, 0.4, 0.1},
             {400, 1, 1, 0.9, 0.6},
             {1500, 1, 1, 1, 0.9}}}}},
         {"shading",
          {{"ambient", 0.2}, {"diffuse", 0.7}, {"specular", 0.3}, {"shininess", 20}}}}}}};
  const std::filesystem::path file = dir / "scene.json";
  std::ofstream(file) << scene.dump(1);
  return file;
}

// Columns: the index axes turned 35 degrees about (1, 2, 3), pitches 1.0, 1.3 and 0.8 mm, the
// first axis reversed when `mirrored` (a left-handed grid, as a NIfTI stored RAS is in LPS).
glm::dmat4 oblique(bool mirrored) {
  glm::dmat4 m =
      glm::rotate(glm::dmat4(1.0), glm::radians(35.0), glm::normalize(glm::dvec3(1, 2, 3)));
  m = glm::scale(m, glm::dvec3(mirrored ? -1.0 : 1.0, 1.3, 0.8));
  m[3] = glm::dvec4(10.0, -20.0, 5.0, 1.0);
  return m;
}

// The share of pixels the volume lights up (over the black background).
double coverage(const Image& image) {
  size_t covered = 0;
  for (size_t i = 0; i < image.size(); ++i) {
    const glm::vec4& p = image.data()[i];
    covered += p.r + p.g + p.b > 0.05f;
  }
  return static_cast<double>(covered) / static_cast<double>(image.size());
}

class PeerScene : public ::testing::TestWithParam<bool> {};

TEST_P(PeerScene, PutsTheVolumeOnItsAxesAndShowsTheSameImage) {
  TempDir dir;
  const std::filesystem::path scene = write_scene(dir, oblique(GetParam()));
  const std::filesystem::path peer = dir / "peer";
  CliResult r = run_lab("bench " + scene.string() + " --write-peer-scene " + peer.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, (peer / "scene.json").string())) << r.output;

  // On VTK's axes: no direction, no offset, the pitches along i, j, k.
  const VolumeData written = read_volume(peer / "volume-0.mha");
  const glm::dvec3 pitch(1.0, 1.3, 0.8);
  for (int c = 0; c < 4; ++c)
    for (int row = 0; row < 3; ++row)
      EXPECT_NEAR(written.index_to_world[c][row], c == row ? pitch[c] : 0.0, 1e-5)
          << "column " << c << " row " << row;

  RenderOptions options;
  options.method = "mdvr";
  const Image original = render(load_scene(scene), options);
  const Image as_peer = render(load_scene(peer / "scene.json"), options);
  // A view of the volume that leaves room around it, so that a misplaced one would show.
  ASSERT_GT(coverage(original), 0.1);
  ASSERT_LT(coverage(original), 0.9);
  // The same rays through the same voxels, up to rounding of the moved camera (a wrong mirror
  // or turn scores under 10 dB).
  EXPECT_GT(psnr(original, as_peer), 45.0);
}

INSTANTIATE_TEST_SUITE_P(Grids, PeerScene, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "Mirrored" : "Turned"; });

// bench --write-peer-scene on `scene` writes its volume placed by `index_to_world` as it is.
void expect_written_in_world_space(const TempDir& dir, const std::filesystem::path& scene,
                                   const glm::dmat4& index_to_world) {
  CliResult r =
      run_lab("bench " + scene.string() + " --write-peer-scene " + (dir / "peer").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const VolumeData written = read_volume(dir / "peer" / "volume-0.mha");
  for (int c = 0; c < 4; ++c)
    for (int row = 0; row < 3; ++row)
      EXPECT_NEAR(written.index_to_world[c][row], index_to_world[c][row], 1e-5);
}

// A sheared grid (gantry tilt) has no frame of its own: it is written in world space as it is.
TEST(PeerSceneSheared, KeepsTheGridAsItIs) {
  TempDir dir;
  glm::dmat4 m(1.0);
  m[2] = glm::dvec4(0.0, 0.4, 1.0, 0.0);  // k leans along y: a 22 degree tilt
  const std::filesystem::path scene = write_scene(dir, m);
  expect_written_in_world_space(dir, scene, m);
}

// Streamlines the peer reads from their own file, in world space: the volume stays there too.
TEST(PeerSceneStreamlines, KeepEverythingInWorldSpace) {
  TempDir dir;
  const glm::dmat4 m = oblique(true);
  const std::filesystem::path scene = write_scene(dir, m);
  std::vector<float> line;
  for (int i = 0; i <= 10; ++i) line.insert(line.end(), {2.0f * i, 0.0f, 0.0f});
  test::write_mrtrix_tracks(dir / "line.tck", "mrtrix tracks", {line}, 3);
  nlohmann::json j = nlohmann::json::parse(std::ifstream(scene));
  j["objects"].push_back({{"name", "tract"},
                          {"type", "streamlines"},
                          {"source", {{"file", (dir / "line.tck").string()}}}});
  std::ofstream(scene) << j.dump(1);
  expect_written_in_world_space(dir, scene, m);
}

TEST(PeerSceneFolder, MustBeNew) {
  TempDir dir;
  const std::filesystem::path scene = write_scene(dir, glm::dmat4(1.0));
  CliResult r = run_lab("bench " + scene.string() + " --write-peer-scene " + dir.path().string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(contains(r.output, "it exists")) << r.output;
}

}  // namespace
}  // namespace imx::test
