// `intermix render lh.pial sig.nii.gz`: a FreeSurfer per-vertex map stored as a NIfTI volume
// (7x1x6 voxels for 42 vertices, as 163842 become 27307x1x6) colours the surface before it,
// vertex v taking voxel v (x fastest; the order is checked against nibabel in
// tests/io/vertex_volume_test.cpp), exactly as a curvature file of the same values does.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "freesurfer_files.hpp"
#include "intermix/io.hpp"
#include "intermix/scene.hpp"
#include "scene/scene_from_files.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

// A closed FreeSurfer surface of 2 + 4 * 10 = 42 vertices: poles and four rings.
void write_surface(const std::filesystem::path& file) {
  test::write_freesurfer_sphere(file, 5, 10);
}

// `values` as a float volume of `dims`, x fastest.
void write_values(const std::filesystem::path& file, glm::ivec3 dims,
                  const std::vector<float>& values) {
  VolumeData v;
  v.dims = dims;
  v.voxels = values;
  write_nifti(v, file, file.extension() == ".gz");
}

std::vector<float> signed_values() {
  std::vector<float> v(42);
  for (size_t i = 0; i < v.size(); ++i)
    v[i] = static_cast<float>(2.0 * std::sin(0.7 * static_cast<double>(i)) + 0.05 * i);
  return v;
}

TEST(CliSurfaceData, APerVertexNiftiAfterItsSurfaceColoursItLikeACurvatureFile) {
  test::TempDir dir;
  write_surface(dir / "lh.pial");
  const std::vector<float> values = signed_values();
  write_values(dir / "sig.nii.gz", {7, 1, 6}, values);
  test::write_freesurfer_curv(dir / "lh.sig", values);
  const std::string png = (dir / "sig.png").string(), saved = (dir / "sig.json").string();
  const test::CliResult r = test::run_cli(
      fmt::format("render {} {} -o {} --width 64 --height 64 --save-scene {}",
                  (dir / "lh.pial").string(), (dir / "sig.nii.gz").string(), png, saved));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json document = nlohmann::json::parse(test::read_bytes(saved));
  ASSERT_EQ(document["objects"].size(), 1u) << document.dump(2);  // no volume object
  const nlohmann::json& overlay = document["objects"][0]["overlay"];
  EXPECT_EQ(overlay["file"], (dir / "sig.nii.gz").string());
  const Scene from_cli = load_scene(saved);
  const SceneDocument from_curv = scene_from_files({dir / "lh.pial", dir / "lh.sig"}, "left", {});
  for (const char* key : {"colormap", "range", "symmetric"})
    EXPECT_EQ(overlay[key], from_curv.json()["objects"][0]["overlay"][key]) << key;
  const std::vector<glm::vec3>& a = from_cli.meshes.at(0).mesh->colors;
  const std::vector<glm::vec3>& b = from_curv.scene().meshes.at(0).mesh->colors;
  ASSERT_EQ(a.size(), b.size());
  ASSERT_FALSE(a.empty());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << "vertex " << i;
  // The same values in another voxel order colour other vertices: the check can fail.
  std::vector<float> swapped = values;
  std::swap(swapped[3], swapped[30]);
  write_values(dir / "swapped.nii", {7, 1, 6}, swapped);
  const SceneDocument other = scene_from_files({dir / "lh.pial", dir / "swapped.nii"}, "left", {});
  EXPECT_NE(other.scene().meshes.at(0).mesh->colors, b);
}

TEST(CliSurfaceData, AThreeDimensionalImageAfterASurfaceStaysAVolume) {
  test::TempDir dir;
  write_surface(dir / "lh.pial");
  // 42 voxels, as many as the surface's vertices, but no axis of 1: an image.
  write_values(dir / "cube.nii", {2, 3, 7}, signed_values());
  const SceneDocument doc = scene_from_files({dir / "lh.pial", dir / "cube.nii"}, "left", {});
  ASSERT_EQ(doc.json()["objects"].size(), 2u);
  EXPECT_EQ(doc.json()["objects"][1]["type"], "volume");
  EXPECT_FALSE(doc.json()["objects"][0].contains("overlay"));
  // An axis of 1 but another count: a volume too (a single slice).
  write_values(dir / "slice.nii", {6, 8, 1}, std::vector<float>(48, 1.0f));
  EXPECT_EQ(
      scene_from_files({dir / "lh.pial", dir / "slice.nii"}, "left", {}).json()["objects"].size(),
      2u);
}

// An overlay with no value that is a number has nothing to colour by: one line that says so,
// not a request for a transfer function (issue 48).
TEST(CliSurfaceData, AnOverlayOfOnlyNanIsNamedAsSuch) {
  test::TempDir dir;
  write_surface(dir / "lh.pial");
  test::write_freesurfer_curv(dir / "lh.nan", std::vector<float>(42, std::nanf("")));
  const test::CliResult r = test::run_cli(
      fmt::format("render {} {} -o {} --width 32 --height 32", (dir / "lh.pial").string(),
                  (dir / "lh.nan").string(), (dir / "nan.png").string()));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(test::contains(r.output, "lh.nan: none of its 42 values is a number")) << r.output;
  EXPECT_FALSE(test::contains(r.output, "transfer_function")) << r.output;
}

}  // namespace
}  // namespace imx
