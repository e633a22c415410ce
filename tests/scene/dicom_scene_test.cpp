// A DICOM series as a scene's volume source: the series choice, its window as the MPR default,
// the notes loading leaves, and the keys only DICOM sources take.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include "intermix/scene.hpp"
#include "test_helpers.hpp"

namespace imx {
namespace {

using test::parse;
using test::parse_error;

const std::filesystem::path kPhilips = std::filesystem::path(IMX_SHARED_DATA) / "dicom/ct-philips";

std::string dicom_scene(const std::string& source, const std::string& plane_keys = "") {
  return fmt::format(
      R"({{"objects": [{{"name": "ct", "type": "volume", "source": {},
            "transfer_function": {{"preset": "ct-bone"}}}},
          {{"name": "axial", "type": "plane", "volume": "ct", "normal": [0, 0, 1]{}}}]}})",
      source, plane_keys);
}

TEST(DicomScene, AFolderLoadsItsSeriesWithItsWindowAndANote) {
  if (!std::filesystem::exists(kPhilips)) GTEST_SKIP() << "no " << kPhilips;
  Scene s = parse(dicom_scene(fmt::format(R"({{"file": "{}"}})", kPhilips.string())));
  const VolumeObject& ct = s.volumes[0];
  EXPECT_EQ(ct.data->dims, glm::ivec3(512, 512, 28));
  ASSERT_TRUE(ct.display_window.has_value());
  EXPECT_GT(ct.display_window->y, 0.0);
  // The plane has no window of its own: it takes the series'.
  EXPECT_EQ(s.planes[0].window, *ct.display_window);
  // The same series by number, and a plane window that overrides the series'.
  Scene by_number =
      parse(dicom_scene(fmt::format(R"({{"file": "{}", "series": 201}})", kPhilips.string()),
                        R"(, "window": [40, 80])"));
  EXPECT_EQ(by_number.volumes[0].data->dims, ct.data->dims);
  EXPECT_EQ(by_number.planes[0].window, glm::dvec2(40.0, 80.0));
}

TEST(DicomScene, WithSeveralSeriesTheLargestLoadsAndANoteSaysWhich) {
  const std::filesystem::path ge = std::filesystem::path(IMX_SHARED_DATA) / "dicom/ct-ge-tilt";
  if (!std::filesystem::exists(kPhilips) || !std::filesystem::exists(ge))
    GTEST_SKIP() << "no " << kPhilips << " or " << ge;
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
  if (!std::filesystem::exists(kPhilips)) GTEST_SKIP() << "no " << kPhilips;
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
