// The reading views' thick slabs and oblique planes through the viewer's messages: a `slice`
// with a thick slab is the max over the voxels across it, an oblique one says its frame, a probe
// gives the trilinear sample; hostile slabs and rotations get one clear error each; a volume's
// "slabs" is kept in the document by an edit and refused when out of range.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/volume.hpp"
#include "server/reading_views.hpp"
#include "server/viewer_state.hpp"
#include "temp_dir.hpp"

namespace imx::server {
namespace {

using Json = nlohmann::json;

float value_of(int i, int j, int k) {
  return static_cast<float>((i * 73 + j * 151 + k * 337 + i * j * k * 17) % 997);
}

// 16^3 voxels of 1 mm, voxel (i, j, k) at world (i, j, k).
ViewerState state_of(const test::TempDir& dir, const std::string& more = "") {
  VolumeData v;
  v.dims = glm::ivec3(16);
  std::vector<float> voxels(16 * 16 * 16);
  for (int k = 0; k < 16; ++k)
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 16; ++i)
        voxels[static_cast<size_t>(i + 16 * (j + 16 * k))] = value_of(i, j, k);
  v.voxels = std::move(voxels);
  write_nrrd(v, dir / "v.nrrd");
  test::write_bytes(dir / "scene.json", R"({"objects": [{"name": "v", "type": "volume",
      "source": {"file": "v.nrrd"}, "window": [500, 1000])" +
                                            more + "}]}");
  return load_viewer_state(dir / "scene.json");
}

Json slice(const std::string& view, const glm::dvec3& p) {
  return {{"type", "slice"}, {"view", view},         {"point", {p.x, p.y, p.z}},
          {"width", 16},     {"height", 16},         {"mm_per_pixel", 1.0},
          {"seq", 1},        {"window", {500, 1000}}};
}

std::string error_of(const ViewerState& state, const Json& message) {
  try {
    answer_slice(state, message);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(ThickSlabMessage, AMipSliceIsTheMaximumOverTheVoxelsAcrossTheSlab) {
  test::TempDir dir;
  const ViewerState state = state_of(dir);
  Json m = slice("axial", {7.5, 7.5, 8.0});
  m["thick_slab"] = {{"thickness", 7.0}, {"mode", "mip"}};
  const SliceAnswer a = answer_slice(state, m);
  const Json text = Json::parse(a.text);
  EXPECT_EQ(text["thick_slab"]["mode"], "mip");
  EXPECT_EQ(text["thick_slab"]["thickness"], 7.0);
  test::write_bytes(dir / "a.png", a.png);
  const Image image = read_png(dir / "a.png", true);  // the stored (display) bytes
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      float most = 0.0f;
      for (int k = 5; k <= 11; ++k) most = std::max(most, value_of(x, y, k));
      ASSERT_NEAR(image.at(x, y).r * 1000.0f, most, 1000.0f / 255.0f) << x << ", " << y;
    }
}

TEST(ThickSlabMessage, AnObliqueSliceSaysItsFrameAndAProbeItsTrilinearSample) {
  test::TempDir dir;
  const ViewerState state = state_of(dir);
  Json m = slice("coronal", {7.5, 7.5, 7.5});
  const double c = std::cos(0.5), s = std::sin(0.5);
  m["rotation"] = {{c, -s, 0}, {s, c, 0}, {0, 0, 1}};  // 0.5 rad about S
  const Json text = Json::parse(answer_slice(state, m).text);
  // The coronal normal (P) turned about S; down stays inferior.
  EXPECT_NEAR(text["normal"][0].get<double>(), -s, 1e-9);
  EXPECT_NEAR(text["normal"][1].get<double>(), c, 1e-9);
  EXPECT_NEAR(text["down"][2].get<double>(), -1.0, 1e-9);
  const glm::dvec3 p(6.3, 7.8, 9.45);
  const Json probe = answer_probe(state, {{"type", "probe"}, {"point", {p.x, p.y, p.z}}});
  const glm::dvec3 f = p - glm::floor(p);
  double want = 0.0;
  for (int k = 0; k < 8; ++k) {
    const glm::ivec3 o(k & 1, (k >> 1) & 1, (k >> 2) & 1);
    const glm::ivec3 i = glm::ivec3(glm::floor(p)) + o;
    want += (o.x ? f.x : 1 - f.x) * (o.y ? f.y : 1 - f.y) * (o.z ? f.z : 1 - f.z) *
            value_of(i.x, i.y, i.z);
  }
  EXPECT_NEAR(probe["values"][0]["sample"].get<double>(), want, 1e-6);
  EXPECT_EQ(probe["values"][0]["value"].get<double>(), value_of(6, 8, 9));  // the nearest voxel's
}

TEST(ThickSlabMessage, HostileSlabsAndRotationsGetOneClearErrorEach) {
  test::TempDir dir;
  const ViewerState state = state_of(dir);
  const struct {
    const char* key;
    Json value;
    const char* says;
  } bad[] = {
      {"thick_slab", {{"thickness", 1e6}}, "thickness: 1000000.0 is not in [0, 1000]"},
      {"thick_slab", {{"thickness", -1}}, "thickness: -1"},
      {"thick_slab", {{"thickness", 5}, {"mode", "max"}}, "mode: \"max\""},
      {"thick_slab", {{"thickness", 5}, {"depth", 1}}, "depth"},
      {"thick_slab", {{"mode", "mip"}}, "thickness"},
      {"thick_slab", 5, "thick_slab"},
      {"rotation", {{1, nullptr, 0}, {0, 1, 0}, {0, 0, 1}}, "rotation[0][1]: expected a number"},
      {"rotation", {{1, 0, 0}, {1, 0, 0}, {0, 0, 1}}, "rotation: is not a rotation"},
      {"rotation", {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, "rotation: is not a rotation"},
      {"rotation", {{-1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, "determinant is -1"},
      {"rotation", {{1, 0, 0}, {0, 1, 0}}, "rotation: expected 3 rows"},
      {"rotation", {{2, 0, 0}, {0, 1, 0}, {0, 0, 1}}, "rotation[0][0]: 2"},
  };
  for (const auto& b : bad) {
    Json m = slice("axial", {7.5, 7.5, 8.0});
    m[b.key] = b.value;
    const std::string said = error_of(state, m);
    EXPECT_NE(said.find(b.says), std::string::npos) << b.value.dump() << ": " << said;
    EXPECT_NE(said.find("slice: "), std::string::npos) << said;
    EXPECT_EQ(said.find('\n'), std::string::npos) << said;
  }
  // Nothing lost: the next slice is answered.
  EXPECT_FALSE(answer_slice(state, slice("axial", {7.5, 7.5, 8.0})).png.empty());
}

TEST(ThickSlabMessage, AVolumesSlabsAreKeptInTheDocument) {
  test::TempDir dir;
  ViewerState state = state_of(dir, R"(, "slabs": {"coronal": {"thickness": 12, "mode": "mean"}})");
  EXPECT_EQ(state.scene().volumes[0].reading_slabs[1].thickness, 12.0);
  EXPECT_EQ(state.scene().volumes[0].reading_slabs[1].mode, SlabMode::mean);
  const Json edit = {{"type", "edit"},
                     {"object", "v"},
                     {"slabs", {{"axial", {{"thickness", 8.5}, {"mode", "minip"}}}}}};
  EXPECT_FALSE(apply_edit(state, edit)) << "a 2-D views' slab re-renders no 3-D frame";
  EXPECT_EQ(state.document.json()["objects"][0]["slabs"],
            Json({{"axial", {{"thickness", 8.5}, {"mode", "minip"}}}}));
  EXPECT_EQ(state.scene().volumes[0].reading_slabs[0].mode, SlabMode::minip);
  EXPECT_EQ(state.scene().volumes[0].reading_slabs[1].thickness, 0.0);
  // Out of range: one error, the document as it was.
  Json hostile = edit;
  hostile["slabs"]["axial"]["thickness"] = 1e6;
  try {
    apply_edit(state, hostile);
    ADD_FAILURE() << "a slab of 1e6 mm was taken";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("slabs.axial.thickness"), std::string::npos) << e.what();
  }
  EXPECT_EQ(state.scene().volumes[0].reading_slabs[0].thickness, 8.5);
  // A scene file's slab on a plane shows no volume: refused.
  test::write_bytes(dir / "plane.json", R"({"objects": [{"name": "p", "type": "plane",
      "center": [0, 0, 0], "normal": [0, 0, 1], "size": 10, "slab": {"thickness": 3}}]})");
  try {
    load_viewer_state(dir / "plane.json");
    ADD_FAILURE() << "a slab on a plane without a volume was taken";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("slab"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace imx::server
