#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "homogeneous_volume.hpp"
#include "methods/reference/reference_kernel.hpp"

namespace imx {
namespace {

using test::homogeneous_volume;

ReferenceParams exact_params(double step) {
  ReferenceParams p;
  p.step = step;
  p.ert = 1.0f;  // no early termination: compare with the closed form
  return p;
}

TEST(ReferenceKernel, HomogeneousVolumeTransmittanceMatchesTheClosedForm) {
  for (float alpha : {0.05f, 0.3f}) {
    for (double step : {0.125, 0.37}) {
      VolumeObject obj = homogeneous_volume(alpha, {1.0f, 0.5f, 0.25f});
      std::vector<PreparedVolume> vols{PreparedVolume(obj)};
      Ray ray{{0.3f, -100.0f, -0.7f}, {0.0f, 1.0f, 0.0f}};
      glm::vec4 c = trace_reference(ray, {}, vols, {}, exact_params(step));
      double transmittance = std::pow(1.0 - alpha, 20.0);
      EXPECT_NEAR(1.0 - c.a, transmittance, 1e-3) << alpha << " " << step;
      EXPECT_NEAR(c.g, 0.5 * c.a, 1e-4);
    }
  }
}

TEST(ReferenceKernel, SurfaceIsSplicedAtItsExactDepth) {
  float alpha = 0.1f;
  VolumeObject obj = homogeneous_volume(alpha, {0.0f, 0.0f, 1.0f});
  std::vector<PreparedVolume> vols{PreparedVolume(obj)};
  Ray ray{{0.0f, -100.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};  // volume spans t in [90, 110]
  for (float depth : {93.3f, 101.7f}) {
    Fragment surface{depth, glm::vec4(0.5f, 0.0f, 0.0f, 0.5f), 1, 1};
    glm::vec4 c = trace_reference(ray, {&surface, 1}, vols, {}, exact_params(0.3));
    double front = 1.0 - std::pow(1.0 - alpha, depth - 90.0);  // volume opacity before it
    double back = 1.0 - std::pow(1.0 - alpha, 110.0 - depth);
    double red = (1.0 - front) * 0.5;
    double blue = front + (1.0 - front) * 0.5 * back;
    EXPECT_NEAR(c.r, red, 1e-4) << depth;
    EXPECT_NEAR(c.b, blue, 1e-4) << depth;
  }
}

TEST(ReferenceKernel, CoincidentSurfacesMixInsteadOfFighting) {
  Fragment a{50.0f, glm::vec4(0.6f, 0.0f, 0.0f, 0.6f), 0, 1};
  Fragment b{50.0f, glm::vec4(0.0f, 0.6f, 0.0f, 0.6f), 1, 1};
  Ray ray{{0, 0, 0}, {0, 0, 1}};
  Fragment ab[2] = {a, b}, ba[2] = {b, a};
  glm::vec4 c1 = trace_reference(ray, ab, {}, {}, ReferenceParams{});
  glm::vec4 c2 = trace_reference(ray, ba, {}, {}, ReferenceParams{});
  EXPECT_NEAR(c1.r, c2.r, 1e-6);
  EXPECT_NEAR(c1.r, c1.g, 1e-6);  // a uniform blend, whichever comes first
  EXPECT_NEAR(c1.a, 1.0 - 0.4 * 0.4, 1e-6);
}

TEST(ReferenceKernel, IsoSurfaceOfASphereFieldLiesAtTheRadius) {
  VolumeObject obj;
  obj.name = "sphere";
  auto data = std::make_shared<VolumeData>();
  data->dims = {41, 41, 41};
  std::vector<float> f;
  for (int k = 0; k < 41; ++k)
    for (int j = 0; j < 41; ++j)
      for (int i = 0; i < 41; ++i)
        f.push_back(12.0f - std::sqrt(float((i - 20) * (i - 20) + (j - 20) * (j - 20) +
                                            (k - 20) * (k - 20))));
  data->voxels = std::move(f);
  obj.data = data;
  obj.index_to_world = glm::translate(glm::dmat4(1.0), glm::dvec3(-20.0));
  obj.style = VolumeStyle::iso;
  obj.iso_value = 0.0;
  obj.transfer_function.points = {{0.0, glm::vec4(0.0f, 1.0f, 0.0f, 1.0f)}};
  std::vector<PreparedVolume> vols{PreparedVolume(obj)};
  // A ray whose first crossing is at distance 12 from the centre: t = 100 - 12.
  Ray ray{{0.0f, -100.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  Fragment behind{95.0f, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f), 1, 1};
  glm::vec4 hidden = trace_reference(ray, {&behind, 1}, vols, {}, ReferenceParams{});
  EXPECT_NEAR(hidden.r, 0.0f, 1e-6f);  // the opaque iso-surface at 88 hides the surface at 95
  EXPECT_NEAR(hidden.g, 1.0f, 1e-6f);
  Fragment before{87.9f, glm::vec4(0.0f, 0.0f, 1.0f, 1.0f), 1, 1};
  glm::vec4 shown = trace_reference(ray, {&before, 1}, vols, {}, ReferenceParams{});
  EXPECT_NEAR(shown.b, 1.0f, 1e-6f);
  Fragment after{88.1f, glm::vec4(0.0f, 0.0f, 1.0f, 1.0f), 1, 1};
  EXPECT_NEAR(trace_reference(ray, {&after, 1}, vols, {}, ReferenceParams{}).b, 0.0f, 1e-6f);
}

}  // namespace
}  // namespace imx
