// The initial 2-D window (volume/display_window.hpp) on synthetic volumes: a header window that
// shows the anatomy is kept, one that shows nothing gives the percentile window with a note.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "volume/display_window.hpp"

namespace imx {
namespace {

// A volume of n^3 voxels whose k-th voxel (in memory order) is value(k / total), as type T.
template <class T, class Field>
VolumeData volume_of(int n, Field value) {
  VolumeData data;
  data.dims = glm::ivec3(n);
  std::vector<T> v(static_cast<size_t>(n) * n * n);
  for (size_t k = 0; k < v.size(); ++k)
    v[k] = static_cast<T>(value(static_cast<double>(k) / static_cast<double>(v.size())));
  data.voxels = std::move(v);
  return data;
}

// A CT in HU: 20% padding at -3024, 30% air about -1000, 40% soft tissue from 0 to 80, 10% bone
// from 700 to 1500.
VolumeData ct() {
  return volume_of<int16_t>(64, [](double f) {
    if (f < 0.2) return -3024.0;
    if (f < 0.5) return -1000.0 + 40.0 * (f - 0.2) / 0.3;
    if (f < 0.9) return 80.0 * (f - 0.5) / 0.4;
    return 700.0 + 800.0 * (f - 0.9) / 0.1;
  });
}

TEST(InitialDisplayWindow, KeepsAHeaderWindowThatShowsTheAnatomy) {
  const InitialWindow w = initial_display_window(ct(), glm::dvec2(40, 80));
  EXPECT_TRUE(w.from_header);
  EXPECT_EQ(w.window, glm::dvec2(40, 80));
  EXPECT_TRUE(w.note.empty()) << w.note;
  // Padding and air are background; of tissue and bone, the tissue (80%) is inside [0, 80].
  EXPECT_GT(w.background, -960.0);
  EXPECT_LT(w.background, 0.0);
  EXPECT_NEAR(w.header_fraction, 0.8, 0.01);
}

TEST(InitialDisplayWindow, APhantomWhoseHeaderWindowShowsNothingGetsItsPercentiles) {
  // Half zeros (the background), half values spread evenly over [1000, 2000]: at L 40 / W 80
  // the phantom is black and white only.
  const VolumeData phantom =
      volume_of<uint16_t>(64, [](double f) { return f < 0.5 ? 0.0 : 1000.0 + 2000.0 * (f - 0.5); });
  const InitialWindow w = initial_display_window(phantom, glm::dvec2(40, 80));
  EXPECT_FALSE(w.from_header);
  EXPECT_EQ(w.header_fraction, 0.0);
  // The 2nd to 98th percentile of [1000, 2000] (above p1 + 10% of the range, so from about 1108):
  // about [1126, 1982].
  const double lo = w.window.x - 0.5 * w.window.y, hi = w.window.x + 0.5 * w.window.y;
  EXPECT_NEAR(lo, 1108.0 + 0.02 * 892.0, 3.0);
  EXPECT_NEAR(hi, 1108.0 + 0.98 * 892.0, 3.0);
  EXPECT_NE(w.note.find("header's window (L 40 / W 80)"), std::string::npos) << w.note;
  EXPECT_NE(w.note.find("0.0%"), std::string::npos) << w.note;
}

TEST(InitialDisplayWindow, TheTwentyPercentLineIsExact) {
  // Zeros, noise from 1 to 10 (both background), then values 300 (a share s of the rest) and
  // 1000; a header window about 300 holds exactly the share s.
  for (const double share : {0.19, 0.21}) {
    const VolumeData v = volume_of<float>(50, [&](double f) {
      if (f < 0.4) return 0.0;
      if (f < 0.5) return 1.0 + 9.0 * (f - 0.4) / 0.1;
      return (f - 0.5) / 0.5 < share ? 300.0 : 1000.0;
    });
    const InitialWindow w = initial_display_window(v, glm::dvec2(300, 20));
    EXPECT_NEAR(w.header_fraction, share, 0.005);
    EXPECT_EQ(w.from_header, share >= kHeaderWindowMinFraction) << share;
    EXPECT_EQ(w.note.empty(), w.from_header) << w.note;
  }
}

TEST(InitialDisplayWindow, WithoutAHeaderWindowThePercentilesOfTheTissueAndNoNote) {
  // An MR: 60% zeros, 10% noise from 1 to 20, then tissue from 200 to 1000.
  const VolumeData mr = volume_of<int16_t>(64, [](double f) {
    if (f < 0.6) return 0.0;
    if (f < 0.7) return 1.0 + 19.0 * (f - 0.6) / 0.1;
    return 200.0 + 800.0 * (f - 0.7) / 0.3;
  });
  const InitialWindow w = initial_display_window(mr, std::nullopt);
  EXPECT_FALSE(w.from_header);
  EXPECT_TRUE(w.note.empty());
  EXPECT_GT(w.background, 20.0);  // the noise is background
  EXPECT_LT(w.background, 200.0);
  const double lo = w.window.x - 0.5 * w.window.y, hi = w.window.x + 0.5 * w.window.y;
  EXPECT_NEAR(lo, 200.0 + 0.02 * 800.0, 4.0);
  EXPECT_NEAR(hi, 200.0 + 0.98 * 800.0, 4.0);
}

TEST(InitialDisplayWindow, ConstantEmptyAndNonFiniteVolumes) {
  const InitialWindow constant =
      initial_display_window(volume_of<float>(8, [](double) { return 7.0; }), glm::dvec2(7, 2));
  EXPECT_TRUE(constant.from_header);  // every voxel lies inside it
  EXPECT_EQ(
      initial_display_window(volume_of<float>(8, [](double) { return 7.0; }), std::nullopt).window,
      glm::dvec2(7, 1));
  const InitialWindow none = initial_display_window(
      volume_of<float>(8, [](double) { return std::numeric_limits<double>::quiet_NaN(); }),
      glm::dvec2(40, 80));
  EXPECT_EQ(none.window, glm::dvec2(0, 1));
  EXPECT_GT(none.window.y, 0.0);
  const InitialWindow empty = initial_display_window(VolumeData{}, std::nullopt);
  EXPECT_EQ(empty.window, glm::dvec2(0, 1));
}

}  // namespace
}  // namespace imx
