// ROI statistics in world space (src/measure/roi_statistics.hpp): on grids of known values, axis
// aligned, rotated and sheared (a gantry tilt), against counts worked out by hand and against a
// brute-force walk of every voxel by the documented rule.
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "measure/measurement.hpp"
#include "measure/roi_statistics.hpp"

namespace imx {
namespace {

// A float volume of `dims` placed by `m`, each voxel's value `f(i, j, k)`.
template <class F>
VolumeObject grid(glm::ivec3 dims, const glm::dmat4& m, F f) {
  auto data = std::make_shared<VolumeData>();
  data->dims = dims;
  data->index_to_world = m;
  std::vector<float> v;
  for (int k = 0; k < dims.z; ++k)
    for (int j = 0; j < dims.y; ++j)
      for (int i = 0; i < dims.x; ++i) v.push_back(static_cast<float>(f(i, j, k)));
  data->voxels = std::move(v);
  VolumeObject o;
  o.name = "v";
  o.units = "HU";
  o.data = data;
  o.index_to_world = m;
  return o;
}

glm::dvec3 centre(const VolumeObject& v, glm::ivec3 i) {
  return glm::dvec3(v.index_to_world * glm::dvec4(glm::dvec3(i), 1.0));
}

Annotation polygon(std::vector<glm::dvec3> corners) {
  return {AnnotationKind::polygon, std::move(corners), "", ""};
}

// A circle of radius r about c in the plane spanned by unit u and v.
Annotation circle(glm::dvec3 c, glm::dvec3 u, glm::dvec3 v, double r) {
  return {AnnotationKind::ellipse, {c, c + r * u, c + r * v}, "", ""};
}

// Every voxel by the rule of roi_statistics.hpp, written out again without its narrowed walk.
std::vector<glm::ivec3> brute_force(const VolumeObject& v, const PlanarRegion& region) {
  const glm::dvec3 n = region.normal();
  double h = 0.0;
  for (int a = 0; a < 3; ++a) h += 0.5 * std::abs(glm::dot(n, glm::dvec3(v.index_to_world[a])));
  std::vector<glm::ivec3> out;
  for (int k = 0; k < v.data->dims.z; ++k)
    for (int j = 0; j < v.data->dims.y; ++j)
      for (int i = 0; i < v.data->dims.x; ++i) {
        const glm::dvec3 w = centre(v, {i, j, k});
        const double d = glm::dot(w - region.origin(), n);
        if (d >= -h && d < h && region.contains(region.in_plane(w))) out.push_back({i, j, k});
      }
  return out;
}

TEST(MeasureRoiStatistics, AxisAlignedRectangleTakesItsSliceVoxels) {
  // 1 x 1 x 2 mm voxels, value i + 100 j + 1000 k, origin off zero.
  const glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(-10, 5, 3)) *
                       glm::scale(glm::dmat4(1.0), glm::dvec3(1, 1, 2));
  const VolumeObject v =
      grid({20, 20, 10}, m, [](int i, int j, int k) { return i + 100 * j + 1000 * k; });
  // Voxels i 3..7, j 4..9 of layer k = 4: the rectangle's edges half a voxel outside.
  const double z = 3 + 2 * 4;
  const Annotation a = polygon({{-10 + 2.5, 5 + 3.5, z},
                                {-10 + 7.5, 5 + 3.5, z},
                                {-10 + 7.5, 5 + 9.5, z},
                                {-10 + 2.5, 5 + 9.5, z}});
  Scene scene;
  scene.volumes.push_back(v);
  const Measurement got = measure(a, scene);
  ASSERT_TRUE(got.statistics);
  const RoiStatistics s = *got.statistics;
  EXPECT_EQ(s.voxels, 30u);
  std::vector<double> values;
  for (int j = 4; j <= 9; ++j)
    for (int i = 3; i <= 7; ++i) values.push_back(i + 100 * j + 4000);
  double mean = 0, var = 0;
  for (double x : values) mean += x / values.size();
  for (double x : values) var += (x - mean) * (x - mean) / values.size();
  EXPECT_NEAR(s.mean, mean, 1e-9);
  EXPECT_NEAR(s.sd, std::sqrt(var), 1e-9);
  EXPECT_EQ(s.min, 3 + 400 + 4000);
  EXPECT_EQ(s.max, 7 + 900 + 4000);
  EXPECT_NEAR(got.area_mm2, 30.0, 1e-9);
  EXPECT_NEAR(got.length_mm, 22.0, 1e-9);
  EXPECT_EQ(got.units, "HU");
}

TEST(MeasureRoiStatistics, CircleCountsTheLatticePointsInside) {
  const VolumeObject v = grid({31, 31, 5}, glm::dmat4(1.0), [](int i, int, int) { return i; });
  const Annotation a = circle({15, 15, 2}, {1, 0, 0}, {0, 1, 0}, 5.0);
  Scene scene;
  scene.volumes.push_back(v);
  const Measurement got = measure(a, scene);
  size_t inside = 0;
  for (int dj = -5; dj <= 5; ++dj)
    for (int di = -5; di <= 5; ++di) inside += di * di + dj * dj <= 25;
  EXPECT_EQ(inside, 81u);
  EXPECT_EQ(got.statistics->voxels, inside);
  EXPECT_NEAR(got.statistics->mean, 15.0, 1e-9);  // symmetric about i = 15
  EXPECT_NEAR(got.area_mm2, 25 * std::numbers::pi, 1e-9);
  EXPECT_NEAR(got.length_mm, 10 * std::numbers::pi, 1e-3);
}

TEST(MeasureRoiStatistics, PlaneBetweenTwoLayersTakesOne) {
  const VolumeObject v = grid({9, 9, 4}, glm::dmat4(1.0), [](int, int, int k) { return k; });
  const Annotation a = polygon({{0, 0, 1.5}, {8, 0, 1.5}, {8, 8, 1.5}, {0, 8, 1.5}});
  const RoiStatistics s = roi_statistics(v, PlanarRegion::of(a));
  // One layer; centres on the edges go by the half-open rule (the low edges' in, the high edges'
  // out), so that two polygons sharing an edge count each voxel once: 8 x 8.
  EXPECT_EQ(s.voxels, 64u);
  EXPECT_EQ(s.min, s.max);
}

TEST(MeasureRoiStatistics, ConcavePolygonLeavesItsNotchOut) {
  const VolumeObject v = grid({10, 10, 1}, glm::dmat4(1.0), [](int, int, int) { return 1; });
  // An L of 6 x 6 less its top-right 3 x 3, around centres 0..5.
  const Annotation a = polygon({{-0.5, -0.5, 0},
                                {5.5, -0.5, 0},
                                {5.5, 2.5, 0},
                                {2.5, 2.5, 0},
                                {2.5, 5.5, 0},
                                {-0.5, 5.5, 0}});
  const PlanarRegion r = PlanarRegion::of(a);
  EXPECT_EQ(roi_voxels(v, r).size(), 27u);
  EXPECT_NEAR(r.area_mm2(), 27.0, 1e-9);
}

TEST(MeasureRoiStatistics, RotatedGridIsExact) {
  // Rotated 30 degrees about x: an axial ROI cuts the layers obliquely. Value: the centre's
  // world x, which the rotation keeps (= i).
  const glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(-32, -32, -32)) *
                       glm::rotate(glm::dmat4(1.0), std::numbers::pi / 6, glm::dvec3(1, 0, 0));
  const VolumeObject v = grid({64, 64, 64}, m, [](int i, int, int) { return i; });
  const glm::dvec3 c(0.3, -20.2, -10.7);  // off every lattice line
  const double r = 10.0;
  const Annotation a = circle(c, {1, 0, 0}, {0, 1, 0}, r);
  const PlanarRegion region = PlanarRegion::of(a);
  const std::vector<glm::ivec3> got = roi_voxels(v, region);
  std::vector<glm::ivec3> want = brute_force(v, region);
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], want[i]) << i;
  // The slab the plane cuts is 2h = sin 30° + cos 30° thick: that many voxels per mm² of ROI.
  const double expected = std::numbers::pi * r * r * (0.5 + std::sqrt(3.0) / 2);
  EXPECT_NEAR(static_cast<double>(got.size()), expected, 0.03 * expected);
  const RoiStatistics s = roi_statistics(v, region);
  EXPECT_NEAR(s.mean, c.x + 32, 0.1);      // x symmetric about the centre
  EXPECT_NEAR(s.sd, r / 2, 0.03 * r / 2);  // a disc's SD along a diameter: r / 2
}

TEST(MeasureRoiStatistics, TiltedGridIsExact) {
  // A gantry tilt: k steps 2 mm along z and 0.7 mm along y; 0.8 mm in-plane pixels. Value j.
  glm::dmat4 m(1.0);
  m[0] = {0.8, 0, 0, 0};
  m[1] = {0, 0.8, 0, 0};
  m[2] = {0, 0.7, 2.0, 0};
  m[3] = {-20, -20, -10, 1};
  const VolumeObject v = grid({50, 50, 12}, m, [](int, int j, int) { return j; });
  // An oblique ellipse and a coronal polygon.
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.2, -0.3, 1.0));
  const glm::dvec3 u = glm::normalize(glm::cross(n, glm::dvec3(0, 1, 0)));
  const Annotation e = {AnnotationKind::ellipse,
                        {{1.1, 0.3, 1.7},
                         glm::dvec3(1.1, 0.3, 1.7) + 8.0 * u,
                         glm::dvec3(1.1, 0.3, 1.7) + 5.0 * glm::cross(n, u)},
                        "",
                        ""};
  const Annotation p = polygon({{-5, 1.3, -4}, {6, 1.3, -3}, {4, 1.3, 6}, {-6, 1.3, 5}});
  for (const Annotation& a : {e, p}) {
    const PlanarRegion region = PlanarRegion::of(a);
    const std::vector<glm::ivec3> got = roi_voxels(v, region);
    const std::vector<glm::ivec3> want = brute_force(v, region);
    ASSERT_GT(got.size(), 20u);
    ASSERT_EQ(got.size(), want.size());
    for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], want[i]) << i;
  }
}

TEST(MeasureRoiStatistics, NonFiniteVoxelsAreCountedApart) {
  const VolumeObject v = grid({5, 5, 1}, glm::dmat4(1.0),
                              [](int i, int j, int) { return i == 2 && j == 2 ? NAN : 10.0; });
  const RoiStatistics s =
      roi_statistics(v, PlanarRegion::of(polygon({{-1, -1, 0}, {5, -1, 0}, {5, 5, 0}})));
  EXPECT_EQ(s.non_finite, 1u);
  EXPECT_EQ(s.mean, 10.0);
  EXPECT_EQ(s.sd, 0.0);
}

TEST(MeasureRoiStatistics, OutsideTheGridIsEmpty) {
  const VolumeObject v = grid({5, 5, 5}, glm::dmat4(1.0), [](int, int, int) { return 1; });
  const RoiStatistics s =
      roi_statistics(v, PlanarRegion::of(circle({100, 0, 0}, {1, 0, 0}, {0, 1, 0}, 3)));
  EXPECT_EQ(s.voxels, 0u);
  EXPECT_TRUE(std::isnan(s.mean));
}

TEST(MeasureRuler, VoxelCentresOfATiltedGrid) {
  const glm::dmat4 m = glm::rotate(glm::dmat4(1.0), 0.4, glm::normalize(glm::dvec3(1, 2, 3))) *
                       glm::scale(glm::dmat4(1.0), glm::dvec3(0.7, 0.9, 2.5));
  const VolumeObject v = grid({16, 16, 16}, m, [](int, int, int) { return 0; });
  const double got = ruler_length(centre(v, {2, 3, 4}), centre(v, {10, 7, 1}));
  const double want = std::sqrt(std::pow(8 * 0.7, 2) + std::pow(4 * 0.9, 2) + std::pow(3 * 2.5, 2));
  EXPECT_NEAR(got, want, 1e-9);
  EXPECT_NEAR(want, 10.0, 0.1);  // sqrt(31.36 + 12.96 + 56.25) = 10.03
}

TEST(MeasureAngle, Degrees) {
  EXPECT_NEAR(angle_degrees({1, 0, 0}, {0, 0, 0}, {0, 3, 0}), 90.0, 1e-12);
  EXPECT_NEAR(angle_degrees({2, 2, 0}, {0, 0, 0}, {5, 0, 0}), 45.0, 1e-12);
  EXPECT_NEAR(angle_degrees({-1, 0, 0}, {0, 0, 0}, {1, 0, 0}), 180.0, 1e-12);
  EXPECT_NEAR(angle_degrees({1, 1e-9, 0}, {0, 0, 0}, {1, 0, 0}), 0.0, 1e-6);
  EXPECT_NEAR(angle_degrees({11, 5, 7}, {10, 5, 7}, {10 + 0.5, 5 + std::sqrt(0.75), 7}), 60.0,
              1e-9);
  EXPECT_TRUE(std::isnan(angle_degrees({0, 0, 0}, {0, 0, 0}, {1, 0, 0})));
  Annotation a{AnnotationKind::angle, {{0, 1, 0}, {0, 0, 0}, {1, 0, 0}}, "", "hip"};
  const Measurement m = measure(a, Scene{});
  EXPECT_NEAR(m.angle_deg, 90.0, 1e-12);
  EXPECT_EQ(measurement_text(a, m), "hip: 90.0°");
}

TEST(Measurements, CsvAndJson) {
  Scene scene;
  scene.volumes.push_back(grid({5, 5, 1}, glm::dmat4(1.0), [](int i, int, int) { return i; }));
  std::vector<Annotation> annotations;
  annotations.push_back({AnnotationKind::ruler, {{0, 0, 0}, {3, 4, 0}}, "", "a, \"b\""});
  annotations.push_back(polygon({{-0.5, -0.5, 0}, {4.5, -0.5, 0}, {4.5, 4.5, 0}, {-0.5, 4.5, 0}}));
  const std::string csv = measurements_csv(scene, annotations);
  EXPECT_NE(csv.find("0,ruler,\"a, \"\"b\"\"\",5,,,,,,,,,,0 0 0; 3 4 0\n"), std::string::npos)
      << csv;
  EXPECT_NE(csv.find("1,polygon,,20,,25,v,HU,25,2,"), std::string::npos) << csv;
  const nlohmann::json j = measurement_json(annotations[1], measure(annotations[1], scene));
  EXPECT_EQ(j["voxels"], 25);
  EXPECT_DOUBLE_EQ(j["mean"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(j["sd"].get<double>(), std::sqrt(2.0));
}

}  // namespace
}  // namespace imx
