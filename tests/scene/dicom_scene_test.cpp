// A DICOM series as a scene's volume source: the series choice, its window as the MPR default,
// the notes loading leaves, and the keys only DICOM sources take; frames of a 4-D source.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

#include <fmt/format.h>

#include "intermix/io.hpp"
#include "intermix/scene.hpp"
#include "scene/reading_planes.hpp"
#include "scene_fixture.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::parse;
using test::parse_error;

const std::filesystem::path kPhilips = test::shared_data("dicom/ct-philips");

std::string dicom_scene(const std::string& source, const std::string& plane_keys = "") {
  return fmt::format(
      R"({{"objects": [{{"name": "ct", "type": "volume", "source": {},
            "transfer_function": {{"preset": "ct-bone"}}}},
          {{"name": "axial", "type": "plane", "volume": "ct", "normal": [0, 0, 1]{}}}]}})",
      source, plane_keys);
}

TEST(DicomScene, AFolderLoadsItsSeriesWithItsWindowAndANote) {
  SKIP_WITHOUT_SHARED_DATA(kPhilips);
  Scene s = parse(dicom_scene(fmt::format(R"({{"file": "{}"}})", kPhilips.string())));
  const VolumeObject& ct = s.volumes[0];
  EXPECT_EQ(ct.data->dims, glm::ivec3(512, 512, 28));
  ASSERT_TRUE(ct.display_window.has_value());
  EXPECT_GT(ct.display_window->y, 0.0);
  // The plane has no window of its own: it takes the reading views' (the series' own when that
  // shows the anatomy; this phantom's 40/80 holds about 5% of its voxels, so its percentiles).
  EXPECT_EQ(s.planes[0].window, reading_window(ct));
  EXPECT_NE(s.planes[0].window, *ct.display_window);
  // The same series by number, and a plane window that overrides the series'.
  Scene by_number =
      parse(dicom_scene(fmt::format(R"({{"file": "{}", "series": 201}})", kPhilips.string()),
                        R"(, "window": [40, 80])"));
  EXPECT_EQ(by_number.volumes[0].data->dims, ct.data->dims);
  EXPECT_EQ(by_number.planes[0].window, glm::dvec2(40.0, 80.0));
}

TEST(DicomScene, WithSeveralSeriesTheLargestLoadsAndANoteSaysWhich) {
  const std::filesystem::path ge = test::shared_data("dicom/ct-ge-tilt");
  SKIP_WITHOUT_SHARED_DATA(kPhilips, ge);
  // The Philips series (28 slices) beside the first 10 slices of the GE series.
  test::TempDir dir;
  for (const auto& e : std::filesystem::directory_iterator(kPhilips))
    std::filesystem::copy_file(e.path(), dir.path() / ("p-" + e.path().filename().string()));
  for (int i = 1; i <= 10; ++i)
    std::filesystem::copy_file(ge / fmt::format("{:02}.dcm", i),
                               dir.path() / fmt::format("g{}.dcm", i));
  Scene s = parse(dicom_scene(fmt::format(R"({{"file": "{}"}})", dir.path().string())));
  EXPECT_EQ(s.volumes[0].data->dims, glm::ivec3(512, 512, 28));
  EXPECT_TRUE(std::any_of(s.notes.begin(), s.notes.end(), [](const std::string& n) {
    return n.find("series 201") != std::string::npos && n.find("of 2 series") != std::string::npos;
  })) << "a note names the series chosen";
  // Asking for the other one by number gives it.
  Scene other =
      parse(dicom_scene(fmt::format(R"({{"file": "{}", "series": 2}})", dir.path().string())));
  EXPECT_TRUE(std::any_of(other.notes.begin(), other.notes.end(), [](const std::string& n) {
    return n.find("loaded series 2 ") != std::string::npos;
  }));
  EXPECT_NE(other.volumes[0].data->index_to_world, s.volumes[0].data->index_to_world);
}

TEST(DicomScene, AnUnknownSeriesIsOneErrorAtTheSource) {
  SKIP_WITHOUT_SHARED_DATA(kPhilips);
  std::string e = parse_error(
      dicom_scene(fmt::format(R"({{"file": "{}", "series": 999}})", kPhilips.string())));
  EXPECT_NE(e.find("objects[0].source"), std::string::npos) << e;
  EXPECT_NE(e.find("999"), std::string::npos) << e;
  EXPECT_NE(e.find("201"), std::string::npos) << "the error lists the series there are: " << e;
}

TEST(DicomScene, DicomKeysOnOtherSourcesAndAnEmptyFileNameAreRefused) {
  std::string e = parse_error(dicom_scene(R"({"phantom": "cube", "size": 8, "series": 2})"));
  EXPECT_NE(e.find("objects[0].source.series"), std::string::npos) << e;
  e = parse_error(dicom_scene(R"({"file": ""})"));
  EXPECT_NE(e.find("empty"), std::string::npos) << "not a scan of the scene's folder: " << e;
}

}  // namespace
}  // namespace imx

namespace imx {
namespace {

// A 4-D source's frame and frame count, the note when none is named, and the note on NaN voxels.
TEST(FrameScene, FrameOfA4dFileAndNotesOnFramesAndNaN) {
  test::TempDir dir;
  std::vector<VolumeData> frames(3);
  for (int f = 0; f < 3; ++f) {
    frames[f].dims = glm::ivec3(4);
    std::vector<float> v(64, static_cast<float>(f));
    v[5] = std::nanf("");
    frames[f].voxels = VoxelBuffer<float>(std::move(v));
  }
  const std::filesystem::path file = dir.path() / "map.nii";
  write_nifti_frames(frames, file, 2.0, false);
  auto scene = [&](const std::string& frame_key) {
    return R"({"objects": [{"name": "map", "type": "volume", "source": {"file": ")" +
           file.string() + "\"" + frame_key +
           R"(}, "transfer_function": {"points": [[0, 0, 0, 0, 0], [2, 1, 1, 1, 1]]}}]})";
  };
  Scene first = parse(scene(""));
  EXPECT_EQ(first.volumes[0].frame, 0);
  EXPECT_EQ(first.volumes[0].frames, 3);
  auto has = [](const Scene& s, const std::string& text) {
    return std::any_of(s.notes.begin(), s.notes.end(),
                       [&](const std::string& n) { return n.find(text) != std::string::npos; });
  };
  EXPECT_TRUE(has(first, "frame 0 of 3"));
  EXPECT_TRUE(has(first, "1 of 64 voxels are NaN or infinite"));
  Scene second = parse(scene(R"(, "frame": 2)"));
  EXPECT_EQ(second.volumes[0].frame, 2);
  EXPECT_EQ(second.volumes[0].data->value_at(0, 0, 0), 2.0);
  EXPECT_FALSE(has(second, "frame 0 of"));
  EXPECT_NE(parse_error(scene(R"(, "frame": 3)")).find("frame 3"), std::string::npos);
}

}  // namespace
}  // namespace imx
