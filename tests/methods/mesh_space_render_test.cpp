// A mesh written in RAS lands on its volume (issue 18): the sphere phantom's iso-surface, made
// analytically, written as 3D Slicer writes a binary STL (x and y negated, "SPACE=RAS" in the
// header), rendered next to the volume: the mesh's first-hit depth meets the volume's iso
// crossing within 0.5 mm along every ray through the sphere.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "intermix/scene.hpp"
#include "phantoms/mesh_primitives.hpp"
#include "probes/first_hit_depth.hpp"

namespace imx {
namespace {

constexpr double kIsoRadius = 0.35 * 128.0;  // where the sphere phantom's value crosses 0
const glm::dvec3 kCentre(20.0, -10.0, 5.0);  // LPS: off the origin, so a lost flip shows

// A binary STL as vtkSTLWriter writes it for Slicer: an 80-byte header naming the space.
void write_slicer_stl(const Mesh& ras, const std::filesystem::path& file) {
  std::string header = "3D Slicer output. SPACE=RAS";
  header.resize(80, ' ');
  std::ofstream out(file, std::ios::binary);
  out.write(header.data(), 80);
  const uint32_t n = static_cast<uint32_t>(ras.triangles.size());
  out.write(reinterpret_cast<const char*>(&n), 4);
  for (const glm::uvec3& t : ras.triangles) {
    const glm::vec3 a = ras.positions[t.x], b = ras.positions[t.y], c = ras.positions[t.z];
    const glm::vec3 normal = glm::normalize(glm::cross(b - a, c - a));
    out.write(reinterpret_cast<const char*>(&normal), 12);
    for (const glm::vec3& p : {a, b, c}) out.write(reinterpret_cast<const char*>(&p), 12);
    out.write("\0\0", 2);
  }
}

std::string scene_json(const std::string& mesh_source) {
  return fmt::format(
      R"({{"camera": {{"eye": [0, -600, 0], "target": [20, -10, 5], "up": [0, 0, 1], "fov_deg": 12}},
          "image": {{"width": 32, "height": 32}},
          "objects": [
            {{"name": "phantom", "type": "volume", "source": {{"phantom": "sphere", "size": 64}},
              "transform": {{"translate": [{}, {}, {}]}}, "style": "iso", "iso_value": 0}},
            {{"name": "surface", "type": "mesh", "source": {}}}]}})",
      kCentre.x, kCentre.y, kCentre.z, mesh_source);
}

struct DepthAgreement {
  int both = 0, only_one = 0;
  double worst = 0.0;
};

DepthAgreement compare(const Scene& scene) {
  const Image volume = first_hit_depth(scene, "phantom");
  const Image mesh = first_hit_depth(scene, "surface");
  DepthAgreement out;
  for (int y = 0; y < volume.height(); ++y)
    for (int x = 0; x < volume.width(); ++x) {
      const float a = volume.at(x, y).r, b = mesh.at(x, y).r;
      if (std::isfinite(a) && std::isfinite(b)) {
        ++out.both;
        out.worst = std::max(out.worst, double(std::abs(a - b)));
      } else if (std::isfinite(a) != std::isfinite(b)) {
        ++out.only_one;
      }
    }
  return out;
}

class MeshSpaceRender : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("imx_mesh_space_render_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    // The iso-surface in LPS, then in RAS as the file holds it.
    glm::dmat4 to_ras(1.0);
    to_ras[0][0] = -1.0;
    to_ras[1][1] = -1.0;
    glm::dmat4 at_centre(1.0);
    at_centre[3] = glm::dvec4(kCentre, 1.0);
    write_slicer_stl(transform_mesh(make_sphere(kIsoRadius, 96), to_ras * at_centre),
                     dir_ / "sphere.stl");
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  std::filesystem::path dir_;
};

TEST_F(MeshSpaceRender, RasMeshMeetsTheVolumesIsoSurface) {
  const Scene scene = parse_scene(scene_json(R"({"file": "sphere.stl"})"), dir_, "scene.json");
  ASSERT_EQ(scene.notes.size(), 1u);
  EXPECT_EQ(scene.notes[0], "mesh 'surface': sphere.stl says SPACE=RAS; converted to LPS");
  const DepthAgreement d = compare(scene);
  std::printf("RAS sphere vs iso crossing: %d rays, worst |dt| = %.4f mm, %d rays hit one only\n",
              d.both, d.worst, d.only_one);
  EXPECT_GT(d.both, 300);  // the sphere covers about half of the 32 x 32 rays
  EXPECT_LT(d.worst, 0.5);
  EXPECT_LE(d.only_one, 8);  // silhouette rays may graze one and miss the other
}

TEST_F(MeshSpaceRender, ReadAsLpsTheSameFileLandsMirrored) {
  const Scene scene =
      parse_scene(scene_json(R"({"file": "sphere.stl", "space": "LPS"})"), dir_, "scene.json");
  EXPECT_TRUE(scene.notes.empty());
  const DepthAgreement d = compare(scene);
  EXPECT_GT(d.only_one + (d.worst > 5.0 ? 1000 : 0), 100);
}

}  // namespace
}  // namespace imx
