// classify_csg_ray on synthetic fragment rows (CSG.md test plan I1-I7).
#include "csg/ray_intervals.hpp"

#include <vector>

#include <gtest/gtest.h>

namespace imx {
namespace {

// A ray's CSG set-up: primitives 0.. are the objects 0.. of the scene order.
struct RaySetup {
  std::vector<ClipState> states;
  std::vector<int8_t> primitive_of_object;
  std::vector<CsgVolumeSpan> spans;
  CsgView view;

  RaySetup(std::vector<std::string> state_digits, int primitives, PrimitiveMask geometric) {
    for (const std::string& d : state_digits) states.push_back(parse_digits(d));
    for (int k = 0; k < primitives; ++k) primitive_of_object.push_back(static_cast<int8_t>(k));
    primitive_of_object.push_back(-1);  // object `primitives`: not in the expression
    spans.resize(primitives);
    view.states = states;
    view.primitive_of_object = primitive_of_object;
    view.geometric = geometric;
    view.meshes = geometric;
    view.used = low_primitives(primitives);
    view.primitive_count = primitives;
  }
};

Fragment fragment(float t, uint32_t object, bool front, float alpha = 0.5f) {
  Fragment f;
  f.t = t;
  f.object = object;
  f.front_facing = front ? 1 : 0;
  f.color = glm::vec4(alpha, 0.0f, 0.0f, alpha);
  return f;
}

struct Classified {
  CsgIntervals result;
  std::vector<Fragment> surfaces;
  std::vector<CsgRange> ranges;
};

// Opacity-presence volumes count as present everywhere in their span unless told otherwise.
Classified classify(const std::vector<Fragment>& row, const RaySetup& s,
                    PrimitiveMask opaque_volumes = ~PrimitiveMask{0}) {
  Classified c;
  c.surfaces.resize(row.size());
  c.ranges.resize(csg_range_capacity(row.size()));
  c.result = classify_csg_ray(
      row, s.view, s.spans, [&](int k, float) { return (opaque_volumes >> k & 1u) != 0; },
      c.surfaces, c.ranges);
  c.surfaces.resize(c.result.surface_count);
  c.ranges.resize(c.result.range_count);
  return c;
}

std::vector<float> depths(const std::vector<Fragment>& surfaces) {
  std::vector<float> t;
  for (const Fragment& f : surfaces) t.push_back(f.t);
  return t;
}

TEST(CsgRayIntervals, NestedMeshesDifference) {  // I1: A - B with B inside A
  RaySetup s({"10"}, 2, 0b11);
  const std::vector<Fragment> row = {fragment(10, 0, true), fragment(20, 1, true),
                                     fragment(30, 1, false), fragment(40, 0, false)};
  Classified c = classify(row, s);
  ASSERT_EQ(c.ranges.size(), 2u);
  EXPECT_EQ(c.ranges[0].t0, 10.0f);
  EXPECT_EQ(c.ranges[0].t1, 20.0f);
  EXPECT_EQ(c.ranges[1].t0, 30.0f);
  EXPECT_EQ(c.ranges[1].t1, 40.0f);
  EXPECT_EQ(c.ranges[0].geometric_inside, PrimitiveMask{0b01});
  EXPECT_FALSE(c.ranges[0].needs_test);
  EXPECT_EQ(depths(c.surfaces), (std::vector<float>{10, 20, 30, 40}));
  EXPECT_FALSE(c.result.inconsistent);
  EXPECT_EQ(c.result.intervals, 3);
}

TEST(CsgRayIntervals, CoplanarFacesOfADifferenceDrawNothing) {  // I2
  RaySetup s({"10"}, 2, 0b11);
  for (float gap : {0.0f, 1e-5f}) {
    const std::vector<Fragment> row = {fragment(10, 0, true), fragment(10 + gap, 1, true),
                                       fragment(30, 1, false), fragment(40, 0, false)};
    Classified c = classify(row, s);
    EXPECT_EQ(depths(c.surfaces), (std::vector<float>{30, 40})) << gap;
    ASSERT_EQ(c.ranges.size(), 1u);
    EXPECT_EQ(c.ranges[0].t0, 30.0f);
  }
}

TEST(CsgRayIntervals, CoplanarFrontsOfAUnionDrawOneMixedSurface) {  // I2
  RaySetup s({"12", "21"}, 2, 0b11);
  const std::vector<Fragment> row = {fragment(10, 0, true, 0.5f), fragment(10, 1, true, 0.5f),
                                     fragment(30, 1, false), fragment(40, 0, false)};
  Classified c = classify(row, s);
  ASSERT_EQ(c.surfaces.size(), 2u);  // the shared front, and A's back (B's is inside A)
  EXPECT_EQ(c.surfaces[0].t, 10.0f);
  EXPECT_NEAR(c.surfaces[0].color.a, 0.75f, 1e-6f);  // M1 of two halves
  EXPECT_EQ(c.surfaces[1].t, 40.0f);
  ASSERT_EQ(c.ranges.size(), 2u);  // cut where B's back changes the geometric bits
  EXPECT_EQ(c.ranges[0].t1, 30.0f);
  EXPECT_EQ(c.ranges[1].t0, 30.0f);
  EXPECT_EQ(c.ranges[1].t1, 40.0f);
}

TEST(CsgRayIntervals, EyeInsideACutterStartsInsideIt) {  // I3
  RaySetup s({"10"}, 2, 0b11);
  // B's entry lies behind the eye: the row holds only its back face.
  const std::vector<Fragment> row = {fragment(10, 0, true), fragment(30, 1, false),
                                     fragment(40, 0, false)};
  Classified c = classify(row, s);
  EXPECT_EQ(depths(c.surfaces), (std::vector<float>{30, 40}));
  ASSERT_EQ(c.ranges.size(), 1u);
  EXPECT_EQ(c.ranges[0].t0, 30.0f);
  EXPECT_EQ(c.ranges[0].t1, 40.0f);
  EXPECT_FALSE(c.result.inconsistent);
}

TEST(CsgRayIntervals, ALostCrossingIsCountedNotMarchedToInfinity) {  // I4
  RaySetup s({"1"}, 1, 0b1);
  Classified c = classify({fragment(10, 0, true)}, s);
  EXPECT_TRUE(c.result.inconsistent);
  EXPECT_TRUE(c.ranges.empty());
  EXPECT_EQ(depths(c.surfaces), (std::vector<float>{10}));
  // Two front faces and no back: the start winding is negative.
  Classified d = classify({fragment(10, 0, true), fragment(20, 0, true)}, s);
  EXPECT_TRUE(d.result.inconsistent);
}

TEST(CsgRayIntervals, AGrazingPairCancels) {  // I5
  RaySetup s({"1"}, 1, 0b1);
  Classified c = classify({fragment(10, 0, true), fragment(10.0001f, 0, false)}, s);
  EXPECT_TRUE(c.surfaces.empty());
  EXPECT_TRUE(c.ranges.empty());
  EXPECT_FALSE(c.result.inconsistent);
}

TEST(CsgRayIntervals, AUnionOfVolumesIsOneRangeOverBothSpans) {  // I6
  RaySetup s({"12", "21"}, 2, 0);
  s.spans = {{10, 50}, {30, 70}};
  Classified c = classify({}, s);
  ASSERT_EQ(c.ranges.size(), 1u);
  EXPECT_EQ(c.ranges[0].t0, 10.0f);
  EXPECT_EQ(c.ranges[0].t1, 70.0f);
  EXPECT_TRUE(c.ranges[0].needs_test);
  EXPECT_EQ(c.result.intervals, 3);  // [10, 30], [30, 50], [50, 70]
  // Spans with a gap: two ranges, the gap is not marched.
  s.spans = {{10, 20}, {30, 70}};
  c = classify({}, s);
  ASSERT_EQ(c.ranges.size(), 2u);
  EXPECT_EQ(c.ranges[0].t1, 20.0f);
  EXPECT_EQ(c.ranges[1].t0, 30.0f);
}

TEST(CsgRayIntervals, OnlyOpacityVolumesInsideNeedATest) {  // I7
  // Mesh A (primitive 0) minus opacity volume V (primitive 1).
  RaySetup s({"10"}, 2, 0b01);
  s.spans = {{}, {20, 30}};
  const std::vector<Fragment> row = {fragment(10, 0, true), fragment(40, 0, false)};
  Classified c = classify(row, s);
  // [10, 20] and [30, 40] hold A alone (certain), [20, 30] depends on V.
  ASSERT_EQ(c.ranges.size(), 1u);  // geometric bits stay {A}: one range
  EXPECT_EQ(c.ranges[0].t0, 10.0f);
  EXPECT_EQ(c.ranges[0].t1, 40.0f);
  EXPECT_TRUE(c.ranges[0].needs_test);
  // Without V on the ray, nothing needs a test.
  s.spans = {{}, {}};
  c = classify(row, s);
  ASSERT_EQ(c.ranges.size(), 1u);
  EXPECT_FALSE(c.ranges[0].needs_test);
}

TEST(CsgRayIntervals, OpacityAtACutDecidesItsSurface) {
  // Mesh A minus opacity volume V whose span covers A's front: A's front is drawn only where
  // V does not show there.
  RaySetup s({"10"}, 2, 0b01);
  s.spans = {{}, {0, 30}};
  const std::vector<Fragment> row = {fragment(10, 0, true), fragment(40, 0, false)};
  EXPECT_EQ(depths(classify(row, s, 0b10).surfaces), (std::vector<float>{40}));
  EXPECT_EQ(depths(classify(row, s, 0).surfaces), (std::vector<float>{10, 40}));
}

TEST(CsgRayIntervals, NonCsgFragmentsPassThroughInOrder) {
  RaySetup s({"1"}, 1, 0b1);
  const std::vector<Fragment> row = {fragment(5, 1, true), fragment(10, 0, true),
                                     fragment(10.0005f, 1, true), fragment(20, 0, false),
                                     fragment(25, 1, false)};
  Classified c = classify(row, s);
  EXPECT_EQ(depths(c.surfaces), (std::vector<float>{5, 10, 10.0005f, 20, 25}));
}

}  // namespace
}  // namespace imx
