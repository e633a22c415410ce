// Sane defaults for scene files: without a camera the scene frames its objects from the
// anterior (or from the "view" it names); without a transfer function a volume gets one chosen
// from what it is (automatic_look.hpp); each choice leaves a note.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/scene.hpp"
#include "scene/automatic_look.hpp"
#include "scene/camera_framing.hpp"
#include "scene/scene_from_files.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

Scene parse(const std::string& text) {
  return parse_scene(text, ".", "scene");
}

// Where a world point falls on the image: (x, y) in [-1, 1] across the width and height.
glm::dvec2 on_image(const Scene& s, const glm::dvec3& p) {
  const glm::dvec3 forward = glm::normalize(s.camera.target - s.camera.eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, s.camera.up));
  const glm::dvec3 up = glm::cross(right, forward);
  const glm::dvec3 d = p - s.camera.eye;
  const double t = std::tan(glm::radians(s.camera.fov_deg) / 2.0);
  const double aspect = static_cast<double>(s.image.width) / s.image.height;
  return {glm::dot(d, right) / glm::dot(d, forward) / (t * aspect),
          glm::dot(d, up) / glm::dot(d, forward) / t};
}

// The largest |x| or |y| of the volume's box corners on the image: in (0, 1] when it fits.
double box_extent_on_image(const Scene& s, const VolumeObject& v) {
  double extent = 0.0;
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 index((c & 1) ? v.data->dims.x - 0.5 : -0.5,
                           (c & 2) ? v.data->dims.y - 0.5 : -0.5,
                           (c & 4) ? v.data->dims.z - 0.5 : -0.5);
    const glm::dvec2 p = on_image(s, glm::dvec3(v.index_to_world * glm::dvec4(index, 1.0)));
    extent = std::max({extent, std::abs(p.x), std::abs(p.y)});
  }
  return extent;
}

const char* kHeadWithoutCamera = R"({"image": {"width": 200, "height": 100},
  "objects": [{"name": "ct", "type": "volume", "source": {"phantom": "ct-head", "size": 32},
               "transfer_function": {"points": [[-2000, 1, 1, 1, 0.1], [3000, 1, 1, 1, 0.1]]}}]})";

TEST(AutomaticCamera, ASceneWithoutCameraFramesItsObjectsFromTheAnterior) {
  const Scene s = parse(kHeadWithoutCamera);
  const VolumeObject& v = s.volumes[0];
  const glm::dvec3 centre(v.index_to_world *
                          glm::dvec4(0.5 * (glm::dvec3(v.data->dims) - 1.0), 1.0));
  EXPECT_LT(glm::length(s.camera.target - centre), 1e-6);
  const glm::dvec3 view = glm::normalize(s.camera.target - s.camera.eye);
  EXPECT_NEAR(view.y, 1.0, 1e-9);  // from the anterior (-y in LPS) towards the posterior
  EXPECT_EQ(s.camera.up, glm::dvec3(0, 0, 1));
  const double extent = box_extent_on_image(s, v);
  EXPECT_LE(extent, 1.0);  // the whole box is on the image...
  EXPECT_GE(extent, 0.8);  // ...and fills most of it
  ASSERT_FALSE(s.notes.empty());
  EXPECT_NE(s.notes.back().find("no camera: looking from the anterior"), std::string::npos)
      << s.notes.back();
}

TEST(AutomaticCamera, AViewTurnsTheCameraToThatPatientDirection) {
  const std::pair<const char*, glm::dvec3> views[] = {
      {"anterior", {0, -1, 0}}, {"posterior", {0, 1, 0}}, {"left", {1, 0, 0}},
      {"right", {-1, 0, 0}},    {"superior", {0, 0, 1}},  {"inferior", {0, 0, -1}}};
  for (const auto& [name, towards_eye] : views) {
    std::string text = kHeadWithoutCamera;
    text.replace(text.find("\"objects\""), 0,
                 std::string("\"camera\": {\"view\": \"") + name + "\", \"fov_deg\": 20}, ");
    const Scene s = parse(text);
    EXPECT_LT(glm::length(glm::normalize(s.camera.eye - s.camera.target) - towards_eye), 1e-9)
        << name;
    EXPECT_EQ(s.camera.fov_deg, 20.0);
    EXPECT_LE(box_extent_on_image(s, s.volumes[0]), 1.0) << name;
    EXPECT_GE(box_extent_on_image(s, s.volumes[0]), 0.8) << name;
  }
}

TEST(AutomaticCamera, ItFramesWhatTheTransferFunctionShowsNotTheEmptyGrid) {
  // Only the bone of the CT phantom shows (above 600 HU): the camera aims at the bone's box.
  const Scene all = parse(kHeadWithoutCamera);
  std::string text = kHeadWithoutCamera;
  text.replace(text.find("[[-2000, 1, 1, 1, 0.1]"), std::string("[[-2000, 1, 1, 1, 0.1]").size(),
               "[[599, 1, 1, 1, 0], [600, 1, 1, 1, 0.5]");
  const Scene bone = parse(text);
  // Bone lies within the head: the bone's box is framed closer than the whole grid.
  EXPECT_LT(glm::length(bone.camera.eye - bone.camera.target),
            glm::length(all.camera.eye - all.camera.target));
  // Nothing shown at all (every alpha 0): the whole grid is framed.
  text = kHeadWithoutCamera;
  text.replace(text.find("0.1]"), 4, "0]");
  text.replace(text.find("0.1]"), 4, "0]");
  const Scene none = parse(text);
  EXPECT_EQ(none.camera.eye, all.camera.eye);
}

TEST(AutomaticCamera, AViewWithAnEyeIsAnError) {
  std::string text = kHeadWithoutCamera;
  text.replace(text.find("\"objects\""), 0, R"("camera": {"view": "left", "eye": [0, -500, 0]}, )");
  try {
    parse(text);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "scene: camera.eye: give either \"view\" (the camera frames the objects) or eye, "
                 "target and up, not both");
  }
  text = kHeadWithoutCamera;
  text.replace(text.find("\"objects\""), 0, R"("camera": {"view": "lateral"}, )");
  EXPECT_THROW(parse(text), Error);
}

TEST(AutomaticLook, AVolumeWithoutTransferFunctionGetsOneByWhatItIs) {
  // The CT phantom's values are Hounsfield units (air -1000, bone above 1000).
  const Scene ct = parse(R"({"objects": [{"name": "ct", "type": "volume",
                                          "source": {"phantom": "ct-head", "size": 32}}]})");
  const Scene bone = parse(R"({"objects": [{"name": "ct", "type": "volume",
                                            "source": {"phantom": "ct-head", "size": 32},
                                            "transfer_function": {"preset": "ct-bone"}}]})");
  ASSERT_EQ(ct.volumes[0].transfer_function.points.size(),
            bone.volumes[0].transfer_function.points.size());
  for (size_t i = 0; i < ct.volumes[0].transfer_function.points.size(); ++i)
    EXPECT_EQ(ct.volumes[0].transfer_function.points[i].value,
              bone.volumes[0].transfer_function.points[i].value);
  EXPECT_EQ(ct.volumes[0].shading.enabled, bone.volumes[0].shading.enabled);
  const bool noted = std::any_of(ct.notes.begin(), ct.notes.end(), [](const std::string& n) {
    return n.find("objects[0] ('ct'): no transfer_function: CT") != std::string::npos;
  });
  EXPECT_TRUE(noted);
}

VolumeData filled(VoxelType type, double (*value)(int i, int j, int k)) {
  VolumeData v;
  v.dims = {20, 20, 20};
  std::vector<float> values(8000);
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 20; ++i)
        values[static_cast<size_t>((k * 20 + j) * 20 + i)] = static_cast<float>(value(i, j, k));
  if (type == VoxelType::f32) {
    v.voxels = std::move(values);
  } else {
    std::vector<uint16_t> u(values.begin(), values.end());
    v.voxels = std::move(u);
  }
  return v;
}

TEST(AutomaticLook, RulesByModalityUnitsAndValues) {
  // MR-like: a grey ramp over the robust range, transparent at its low end.
  const VolumeData mr = filled(VoxelType::u16, [](int i, int, int) { return 10.0 * i; });
  const AutomaticLook grey = automatic_look(mr, "", "");
  ASSERT_TRUE(grey.transfer_function.contains("points"));
  const auto& points = grey.transfer_function["points"];
  EXPECT_EQ(points.front()[4].get<double>(), 0.0);
  EXPECT_GT(points.back()[4].get<double>(), 0.0);
  EXPECT_GT(points.back()[0].get<double>(), points.front()[0].get<double>());
  EXPECT_LE(points.back()[0].get<double>(), 190.0);
  EXPECT_NE(grey.reason.find("grey ramp"), std::string::npos);
  // The same values from a DICOM CT series, or in HU, take the CT preset; PET a hot ramp.
  EXPECT_EQ(automatic_look(mr, "CT", "").transfer_function["preset"], "ct-bone");
  EXPECT_EQ(automatic_look(mr, "", "HU").transfer_function["preset"], "ct-bone");
  EXPECT_NE(automatic_look(mr, "PT", "g/ml").reason.find("PET"), std::string::npos);
  // A t map: both signs, nothing shown between the thresholds.
  const VolumeData t = filled(VoxelType::f32, [](int i, int, int) { return (i - 9.5) * 0.8; });
  const AutomaticLook two_sided = automatic_look(t, "", "");
  EXPECT_NE(two_sided.reason.find("signed map"), std::string::npos);
  const auto& tp = two_sided.transfer_function["points"];
  ASSERT_EQ(tp.size(), 6u);
  EXPECT_LT(tp[1][0].get<double>(), 0.0);
  EXPECT_EQ(tp[2][4].get<double>(), 0.0);
  EXPECT_EQ(tp[3][4].get<double>(), 0.0);
  EXPECT_GT(tp[4][0].get<double>(), 0.0);
  // A mask: one value above a background of zeros (here 1 voxel in 8), shown as a surface.
  const VolumeData mask = filled(
      VoxelType::f32, [](int i, int j, int k) { return i < 10 && j < 10 && k < 10 ? 9.0 : 0.0; });
  const AutomaticLook surface = automatic_look(mask, "", "");
  EXPECT_NE(surface.reason.find("a mask"), std::string::npos) << surface.reason;
  EXPECT_EQ(surface.transfer_function["points"][0][0].get<double>(), 4.5);
  EXPECT_EQ(surface.transfer_function["points"][0][4].get<double>(), 0.0);
  // One value everywhere still gives a valid function.
  const VolumeData flat = filled(VoxelType::f32, [](int, int, int) { return 5.0; });
  EXPECT_TRUE(automatic_look(flat, "", "").transfer_function.contains("points"));
}

TEST(AutomaticLook, LabelMapsAreToldFromImagesByTheirValues) {
  // Tissue classes 0-3; an aseg-like map of 40 values spread over 0-255; and what is not one:
  // an 8-bit ramp filling its span, a mask of two values, non-integer floats.
  EXPECT_TRUE(looks_like_label_map(
      filled(VoxelType::u16, [](int i, int, int) { return i / 5.0 - std::fmod(i / 5.0, 1.0); })));
  EXPECT_TRUE(looks_like_label_map(
      filled(VoxelType::u16, [](int i, int j, int) { return 6.0 * ((i + 20 * j) % 40); })));
  EXPECT_FALSE(looks_like_label_map(
      filled(VoxelType::u16, [](int i, int j, int) { return double((i + 20 * j) % 256); })));
  EXPECT_FALSE(looks_like_label_map(
      filled(VoxelType::f32, [](int i, int, int) { return i < 10 ? 0.0 : 9.0; })));
  EXPECT_FALSE(
      looks_like_label_map(filled(VoxelType::f32, [](int i, int, int) { return i * 0.5; })));
}

TEST(AutomaticLook, AFileSceneDrawsALabelMapInThePalette) {
  test::TempDir dir;
  VolumeData seg = filled(VoxelType::u16, [](int i, int, int) {
    return i < 5 ? 0.0 : i < 10 ? 1.0 : i < 15 ? 2.0 : 3.0;
  });
  write_nifti(seg, dir.path() / "tissues.nii.gz");
  write_nifti(filled(VoxelType::u16, [](int i, int j, int) { return double((i + 20 * j) % 256); }),
              dir.path() / "t1.nii.gz");
  const SceneDocument doc =
      scene_from_files({dir.path() / "t1.nii.gz", dir.path() / "tissues.nii.gz"}, "anterior", {});
  const auto& objects = doc.json()["objects"];
  EXPECT_FALSE(objects[0].contains("style"));
  EXPECT_EQ(objects[1]["style"], "labels");
  EXPECT_FALSE(objects[1].contains("transfer_function"));
  ASSERT_TRUE(doc.scene().volumes[1].labels);
  EXPECT_TRUE(doc.scene().volumes[1].labels->palette_unlisted);
}

TEST(AutomaticLook, EveryRegionChoosesTheSameLookFromSlicesOfTheWhole) {
  const std::string text = R"({"camera": {"eye": [0, -500, 0]}, "objects": [{"name": "s",
      "type": "volume", "source": {"phantom": "shells", "size": 48}}]})";
  const auto file = std::filesystem::temp_directory_path() / "imx_region_auto_tf.json";
  { std::ofstream(file) << text; }
  // A brick of the bottom slices (mostly background) and one through the middle: their own
  // voxels would choose different ramps.
  auto points_of = [&](int z0, int z1) {
    const Scene s = load_scene(file, {}, [&](const std::string&, const VolumeHeader& h) {
      return VoxelBox{{0, 0, z0}, {h.dims.x, h.dims.y, z1}};
    });
    EXPECT_EQ(s.volumes[0].data->dims.z, z1 - z0);
    return s.volumes[0].transfer_function.points;
  };
  const std::vector<TfPoint> bottom = points_of(0, 6), middle = points_of(20, 28);
  ASSERT_EQ(bottom.size(), middle.size());
  ASSERT_GE(bottom.size(), 2u);
  for (size_t i = 0; i < bottom.size(); ++i) {
    EXPECT_EQ(bottom[i].value, middle[i].value);
    EXPECT_EQ(bottom[i].rgba, middle[i].rgba);
  }
  // The control: the bottom brick's own voxels choose another ramp.
  const Scene whole = load_scene(file);
  VolumeData bottom_voxels = crop(*whole.volumes[0].data, {{0, 0, 0}, {48, 48, 6}}, "bottom");
  const AutomaticLook own = automatic_look(bottom_voxels, "", "");
  EXPECT_NE(own.transfer_function.dump(),
            automatic_look(*whole.volumes[0].data, "", "").transfer_function.dump());
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace imx
