// Evidence for a mesh file's space (issue 46): a mesh that lies in the scene's volumes only when
// mirrored (written in RAS, read as LPS, or back) gets a note naming the fix, and stays where it
// was read. A mesh that fits as read, or whose source gives "space", gets none.
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "intermix/io.hpp"
#include "intermix/scene.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

// The volume's centre in LPS: a sphere phantom moved there, so that negating x and y moves a
// mesh out of it.
const glm::vec3 kCentre{60, 70, 30};

// A small tetrahedron at `at`, with `header` lines first.
void write_tetra_obj(const fs::path& file, const glm::vec3& at, const std::string& header = "") {
  std::ofstream out(file);
  out << header;
  for (const glm::vec3& d :
       {glm::vec3(0), glm::vec3(4, 0, 0), glm::vec3(0, 4, 0), glm::vec3(0, 0, 4)})
    out << fmt::format("v {} {} {}\n", at.x + d.x, at.y + d.y, at.z + d.z);
  out << "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
}

// The scene of the volume and the mesh file, with `source_extra` in the mesh's source.
Scene load(const TempDir& dir, const fs::path& mesh, const std::string& source_extra = "") {
  const fs::path scene = dir / "scene.json";
  std::ofstream(scene) << fmt::format(
      R"({{"objects": [
           {{"name": "ball", "type": "volume", "source": {{"phantom": "sphere", "size": 16}},
             "transform": {{"translate": [{}, {}, {}]}}}},
           {{"name": "tetra", "type": "mesh", "source": {{"file": "{}"{}}}}}]}})",
      kCentre.x, kCentre.y, kCentre.z, mesh.filename().string(), source_extra);
  return load_scene(scene);
}

bool has_mirror_note(const Scene& s) {
  for (const std::string& n : s.notes)
    if (n.find("x and y mirrored") != std::string::npos) return true;
  return false;
}

std::string notes(const Scene& s) {
  std::string all;
  for (const std::string& n : s.notes) all += n + "\n";
  return all;
}

TEST(MeshSpaceEvidence, AMeshWrittenInRasBesideAVolumeGetsANoteAndStaysAsRead) {
  TempDir dir;
  const glm::vec3 ras(-kCentre.x, -kCentre.y, kCentre.z);
  write_tetra_obj(dir / "tetra.obj", ras);
  const Scene s = load(dir, dir / "tetra.obj");
  EXPECT_TRUE(has_mirror_note(s)) << notes(s);
  const std::string expected =
      "mesh 'tetra': tetra.obj was read as LPS (it names no space, so the scene's), where its "
      "box is 0% inside the volumes";
  EXPECT_NE(notes(s).find(expected), std::string::npos) << notes(s);
  EXPECT_NE(notes(s).find("read as RAS (x and y mirrored) it would be 100% inside"),
            std::string::npos)
      << notes(s);
  EXPECT_NE(notes(s).find("give its source \"space\": \"RAS\" (on the command line: --set "
                          "objects.tetra.source.space=RAS); it is placed as read"),
            std::string::npos)
      << notes(s);
  // Placement never changes on the evidence: the vertices are the file's, read as LPS.
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].mesh->positions[0], ras);
}

TEST(MeshSpaceEvidence, AMeshThatFitsOrWhoseSpaceIsGivenGetsNoNote) {
  TempDir dir;
  const glm::vec3 ras(-kCentre.x, -kCentre.y, kCentre.z);
  write_tetra_obj(dir / "lps.obj", kCentre);  // written in LPS, read so
  EXPECT_FALSE(has_mirror_note(load(dir, dir / "lps.obj")));
  write_tetra_obj(dir / "tagged.obj", ras, "# SPACE=RAS\n");  // the file says RAS
  const Scene tagged = load(dir, dir / "tagged.obj");
  EXPECT_FALSE(has_mirror_note(tagged)) << notes(tagged);
  EXPECT_EQ(tagged.meshes[0].mesh->positions[0], kCentre);
  write_tetra_obj(dir / "ras.obj", ras);  // the source says it: the user chose
  EXPECT_FALSE(has_mirror_note(load(dir, dir / "ras.obj", R"(, "space": "LPS")")));
  EXPECT_FALSE(has_mirror_note(load(dir, dir / "ras.obj", R"(, "space": "RAS")")));
}

// A file that says SPACE=LPS but holds RAS coordinates: the note names what it said.
TEST(MeshSpaceEvidence, AHeaderThatSaysTheWrongSpaceGetsANote) {
  TempDir dir;
  write_tetra_obj(dir / "wrong.obj", {-kCentre.x, -kCentre.y, kCentre.z}, "# SPACE=LPS\n");
  const Scene s = load(dir, dir / "wrong.obj");
  EXPECT_NE(notes(s).find("wrong.obj was read as LPS (it says SPACE=LPS)"), std::string::npos)
      << notes(s);
}

// A whole brain written in RAS over the MNI template (NiiVue's simplify_brain.obj is one): inside
// the template either way, but centred on it only when mirrored. The left hemisphere of
// BrainMesh_ICBM152 (MZ3, LPS once read) and its mirror image make the brain.
TEST(MeshSpaceEvidence, AWholeBrainInRasOverTheMniTemplateGetsANote) {
  const fs::path template_file = test::shared_data("neuro/volumes/avg152T1_RL_nifti.nii.gz");
  const fs::path hemisphere = test::shared_data("neuro/surfaces/BrainMesh_ICBM152.lh.mz3");
  SKIP_WITHOUT_SHARED_DATA("neuro/surfaces/BrainMesh_ICBM152.lh.mz3");
  TempDir dir;
  const Mesh lh = read_mesh(hemisphere);
  for (const bool ras : {true, false}) {
    SCOPED_TRACE(ras ? "RAS" : "LPS");
    const fs::path file = dir / (ras ? "brain_ras.obj" : "brain_lps.obj");
    std::ofstream out(file);
    for (const float side : {1.0f, -1.0f})
      for (const glm::vec3& p : lh.positions) {
        const glm::vec3 q(side * p.x, p.y, p.z);  // the right hemisphere mirrors the left
        out << fmt::format("v {} {} {}\n", ras ? -q.x : q.x, ras ? -q.y : q.y, q.z);
      }
    const size_t n = lh.positions.size();
    for (const glm::uvec3& t : lh.triangles) {
      out << fmt::format("f {} {} {}\n", t.x + 1, t.y + 1, t.z + 1);
      out << fmt::format("f {} {} {}\n", t.x + n + 1, t.z + n + 1, t.y + n + 1);
    }
    out.close();
    const fs::path scene = dir / "brain.json";
    std::ofstream(scene) << fmt::format(
        R"({{"objects": [{{"name": "mni", "type": "volume", "source": {{"file": "{}"}}}},
                         {{"name": "brain", "type": "mesh", "source": {{"file": "{}"}}}}]}})",
        template_file.string(), file.string());
    const Scene s = load_scene(scene);
    EXPECT_EQ(has_mirror_note(s), ras) << notes(s);
  }
}

}  // namespace
}  // namespace imx
