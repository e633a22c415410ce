// A CIFTI-2 overlay on a surface in scenes: the fs_LR 32k curvature on the left inflated surface
// colours each vertex as a GIfTI shape file of nibabel's values for that vertex does (NaN on
// the medial wall), whether given after the surface or as a mesh's "overlay".
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "../io/nibabel_reference.hpp"
#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "intermix/scene.hpp"
#include "scene/scene_from_files.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using nlohmann::json;

constexpr const char* kSurface = "neuro/surfaces/fs_LR.32k.L.inflated.surf.gii";
constexpr const char* kCurvature = "neuro/surfaces/fs_LR.32k.LR.curvature.dscalar.nii";

std::vector<glm::vec3> colours_with(const test::TempDir& dir, const json& overlay) {
  const json cortex = {{"name", "cortex"},
                       {"type", "mesh"},
                       {"source", {{"file", test::shared_data(kSurface).string()}}},
                       {"material", {{"color", {0.5, 0.5, 0.5}}}},
                       {"overlay", overlay}};
  test::write_bytes(dir / "scene.json", json({{"objects", {cortex}}}).dump(2));
  return load_scene(dir / "scene.json").meshes.at(0).mesh->colors;
}

TEST(CiftiScene, CurvatureColoursTheLeftSurfaceVertexByVertex) {
  SKIP_WITHOUT_SHARED_DATA(kSurface, kCurvature);
  if (!test::have_nibabel()) GTEST_SKIP() << "/usr/bin/python3 with nibabel is not available";
  test::TempDir dir;
  // nibabel's values of the left cortex on its 32492 vertices, as a GIfTI shape file.
  ASSERT_TRUE(test::run_nibabel(
      dir, "img = nib.load('" + test::shared_data(kCurvature).string() + "')\n" + R"PY(
for name, sl, bm in img.header.get_axis(1).iter_structures():
    if name == 'CIFTI_STRUCTURE_CORTEX_LEFT':
        v = np.full(bm.nvertices[name], np.nan, np.float32)
        v[bm.vertex] = np.asarray(img.get_fdata())[0, sl]
nib.save(nib.gifti.GiftiImage(darrays=[nib.gifti.GiftiDataArray(v, intent='NIFTI_INTENT_SHAPE',
         datatype='NIFTI_TYPE_FLOAT32')]), 'left.shape.gii')
)PY"));
  const json coloring = {{"colormap", "cold-hot"}, {"range", {0.0, 0.3}}, {"symmetric", true}};
  json cifti = coloring, gifti = coloring, right = coloring;
  cifti["file"] = test::shared_data(kCurvature).string();  // the structure from the surface
  gifti["file"] = (dir / "left.shape.gii").string();
  right["file"] = cifti["file"];
  right["structure"] = "CORTEX_RIGHT";
  const std::vector<glm::vec3> a = colours_with(dir, cifti), b = colours_with(dir, gifti),
                               c = colours_with(dir, right);
  ASSERT_EQ(a.size(), b.size());
  int differing = 0, base = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i] != b[i] && differing++ < 5)
      ADD_FAILURE() << "vertex " << i << ": " << a[i].r << "," << a[i].g << "," << a[i].b
                    << " where the shape file gives " << b[i].r << "," << b[i].g << "," << b[i].b;
    base += a[i] == glm::vec3(1.0f);  // the medial wall: no value
    // The right hemisphere's map on the left surface is another colouring altogether.
  }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(base, 1000);  // 32492 - 29696 medial-wall vertices (split by computed normals)
  size_t other = 0;
  for (size_t i = 0; i < a.size(); ++i) other += a[i] != c[i];
  EXPECT_GT(other, a.size() / 2);

  // "frame" past the file's one map, "structure" on a file that has none of them.
  json bad = cifti;
  bad["frame"] = 1;
  test::expect_error([&] { colours_with(dir, bad); },
                     {"objects[0].overlay.file", "map 1 asked for; it has 1 maps"});
  bad = cifti;
  bad["structure"] = "CEREBELLUM";
  test::expect_error([&] { colours_with(dir, bad); },
                     {"no surface structure CEREBELLUM", "CORTEX_LEFT (32492 vertices)"});
  bad = gifti;
  bad["structure"] = "CORTEX_LEFT";
  test::expect_error([&] { colours_with(dir, bad); },
                     {"\"structure\" picks a surface structure of a CIFTI-2 file"});
}

TEST(CiftiScene, FromFilesAfterTheSurfaceAndNotAlone) {
  SKIP_WITHOUT_SHARED_DATA(kSurface, kCurvature);
  const std::filesystem::path surface = test::shared_data(kSurface),
                              curvature = test::shared_data(kCurvature);
  SceneDocument doc = scene_from_files({surface, curvature}, "left", {});
  ASSERT_EQ(doc.json()["objects"].size(), 1u);  // the overlay is no object of its own
  const json& overlay = doc.json()["objects"][0]["overlay"];
  EXPECT_EQ(overlay["structure"], "CORTEX_LEFT");
  EXPECT_EQ(overlay["colormap"], "cold-hot");  // curvature is signed
  EXPECT_FALSE(overlay.contains("frame"));     // one map
  EXPECT_FALSE(doc.scene().meshes[0].mesh->colors.empty());
  test::expect_error([&] { scene_from_files({curvature}, "left", {}); },
                     {"is a CIFTI-2 file of surface data: give it after its surfaces"});
}

}  // namespace
}  // namespace imx
