#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "homogeneous_volume.hpp"
#include "methods/mdvr/mdvr_kernel.hpp"
#include "methods/reference/reference_kernel.hpp"

namespace imx {
namespace {

using test::homogeneous_volume;

TEST(MdvrKernel, SurfacesAloneCompositeInDepthOrder) {
  Fragment f[2] = {{10.0f, glm::vec4(0.5f, 0, 0, 0.5f), 0, 1},
                   {20.0f, glm::vec4(0, 0.8f, 0, 0.8f), 1, 1}};
  Ray ray{{0, 0, 0}, {0, 0, 1}};
  glm::vec4 c = trace_mdvr(ray, f, {}, {}, MdvrParams{});
  EXPECT_NEAR(c.r, 0.5f, 1e-6f);
  EXPECT_NEAR(c.g, 0.4f, 1e-6f);
  EXPECT_NEAR(c.a, 0.9f, 1e-6f);
}

TEST(MdvrKernel, SurfaceIsCompositedBeforeTheFirstSampleBehindIt) {
  VolumeObject obj = homogeneous_volume(0.2f, {0, 0, 1});
  std::vector<PreparedVolume> vols{PreparedVolume(obj)};
  Ray ray{{0, -100, 0}, {0, 1, 0}};  // volume over t in [90, 110]; samples at 90, 91, ..., 110
  MdvrParams p;
  p.step = 1.0;
  p.ert = 1.0f;
  Fragment surface{95.4f, glm::vec4(0.5f, 0, 0, 0.5f), 1, 1};
  glm::vec4 c = trace_mdvr(ray, {&surface, 1}, vols, {}, p);
  // Samples at 90..95 (six) are in front of the surface, 96..109 (fourteen) behind it.
  double front = 1.0 - std::pow(0.8, 6.0);
  double back = 1.0 - std::pow(0.8, 14.0);
  EXPECT_NEAR(c.r, (1.0 - front) * 0.5, 1e-4);
  EXPECT_NEAR(c.b, front + (1.0 - front) * 0.5 * back, 1e-4);
}

TEST(MdvrKernel, MatchesTheReferenceOnAHomogeneousVolume) {
  VolumeObject obj = homogeneous_volume(0.1f, {1, 1, 1});
  std::vector<PreparedVolume> vols{PreparedVolume(obj)};
  Ray ray{{0.2f, -100, 0.1f}, {0, 1, 0}};
  ReferenceParams rp;
  rp.step = 0.05;
  rp.ert = 1.0f;
  MdvrParams mp;
  mp.step = 1.0;
  mp.ert = 1.0f;
  glm::vec4 ref = trace_reference(ray, {}, vols, {}, rp);
  glm::vec4 mdvr = trace_mdvr(ray, {}, vols, {}, mp);
  // 20 samples of 1 mm over the 20 mm inside: no step counted twice at the exit.
  EXPECT_NEAR(1.0 - ref.a, std::pow(0.9, 20.0), 1e-3);
  EXPECT_NEAR(1.0 - mdvr.a, std::pow(0.9, 20.0), 1e-3);
}

TEST(MdvrKernel, StopsAtTheEarlyTerminationOpacity) {
  VolumeObject obj = homogeneous_volume(0.5f, {1, 1, 1});
  std::vector<PreparedVolume> vols{PreparedVolume(obj)};
  Ray ray{{0, -100, 0}, {0, 1, 0}};
  MdvrParams p;
  p.step = 1.0;
  p.ert = 0.9f;
  Fragment behind{105.0f, glm::vec4(1, 0, 0, 1), 1, 1};
  glm::vec4 c = trace_mdvr(ray, {&behind, 1}, vols, {}, p);
  EXPECT_GE(c.a, 0.9f);
  EXPECT_LT(c.a, 0.97f);         // 4 samples reach 0.9375 and the ray stops there
  EXPECT_NEAR(c.r, c.g, 1e-6f);  // the red surface behind was never composited
}

}  // namespace
}  // namespace imx
