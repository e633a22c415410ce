// Iso-surfaces, projections and clip planes of the volume engine, against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "homogeneous_volume.hpp"
#include "intermix/io.hpp"
#include "methods/mdvr/mdvr_kernel.hpp"
#include "volume/iso_crossing.hpp"
#include "volume/projection.hpp"

namespace imx {
namespace {

// The built-in sphere phantom: value = radius - distance from the centre, radius 0.35 * 128 mm.
VolumeObject sphere_phantom(int size) {
  VolumeObject obj;
  obj.name = "sphere";
  obj.data = std::make_shared<VolumeData>(make_phantom("sphere", size));
  obj.index_to_world = obj.data->index_to_world;
  obj.transfer_function.points = {{-50.0, glm::vec4(0, 0, 0, 0)}, {50.0, glm::vec4(1, 1, 1, 1)}};
  return obj;
}

TEST(VolumeStyles, RefinedIsoSurfaceOfTheSpherePhantomLiesAtTheRadius) {
  VolumeObject obj = sphere_phantom(64);
  obj.style = VolumeStyle::iso;
  obj.iso_value = 0.0;
  PreparedVolume v(obj);
  const double pitch = v.min_pitch, radius = 0.35 * 128.0;
  glm::vec3 centre = glm::vec3(obj.index_to_world * glm::dvec4(glm::dvec3(31.5), 1.0));
  std::mt19937 rng(11);
  std::normal_distribution<float> n(0.0f, 1.0f);
  double worst = 0.0;
  for (int r = 0; r < 200; ++r) {
    glm::vec3 d = glm::normalize(glm::vec3(n(rng), n(rng), n(rng)));
    glm::vec3 aim = centre + 20.0f * glm::vec3(n(rng), n(rng), n(rng)) * 0.3f;
    Ray ray{aim - 200.0f * d, d};
    RayInterval span = v.intersect(ray);
    VolumeHit hit;
    ASSERT_TRUE(find_iso_crossing(v, ray, span.t0, span.t1, pitch, 10, {}, hit));
    double off = glm::length(ray.at(static_cast<float>(hit.t)) - centre) - radius;
    worst = std::max(worst, std::abs(off));
  }
  EXPECT_LT(worst / pitch, 0.05);  // in voxels
}

TEST(VolumeStyles, MipShowsTheMaximumAtItsDepth) {
  VolumeObject obj = sphere_phantom(64);
  obj.style = VolumeStyle::mip;
  PreparedVolume v(obj);
  glm::vec3 centre = glm::vec3(obj.index_to_world * glm::dvec4(glm::dvec3(31.5), 1.0));
  Ray ray{centre - glm::vec3(0, 300, 0), {0, 1, 0}};
  RayInterval span = v.intersect(ray);
  VolumeHit hit;
  ASSERT_TRUE(project_volume(v, ray, span.t0, span.t1, 0.25, hit));
  EXPECT_NEAR(hit.t, 300.0, 1.0);
  // The peak is a cone tip sampled trilinearly: within a voxel diagonal of the radius.
  float peak = v.lut.lookup(static_cast<float>(0.35 * 128.0)).a;
  EXPECT_NEAR(hit.color.a, peak, 0.02f);
}

TEST(VolumeStyles, XrayAverageOfAHomogeneousVolumeIsItsValue) {
  VolumeObject obj = test::homogeneous_volume(0.3f, {0.2f, 0.4f, 0.6f});
  obj.style = VolumeStyle::xray;
  obj.xray_mode = XrayMode::average;
  obj.transfer_function.points = {{0.0, glm::vec4(0)}, {2.0, glm::vec4(0.2f, 0.4f, 0.6f, 1.0f)}};
  PreparedVolume v(obj);
  Ray ray{{0, -100, 0}, {0, 1, 0}};
  VolumeHit hit;
  ASSERT_TRUE(project_volume(v, ray, 90.0, 110.0, 0.7, hit));
  EXPECT_NEAR(hit.t, 100.0, 1e-4);
  EXPECT_NEAR(hit.color.a, 0.5f, 1e-5f);   // TF at value 1
  EXPECT_NEAR(hit.color.b, 0.15f, 1e-5f);  // straight 0.3, premultiplied
}

// The line integral through 20 mm of a medium whose TF opacity 0.5 per mm stands for an
// attenuation of ln 2 per mm: 1 - 2^-20 of the light is absorbed, in the medium's colour.
TEST(VolumeStyles, XrayIntegralOfAHomogeneousVolumeIsItsAttenuation) {
  VolumeObject obj = test::homogeneous_volume(0.3f, {0.2f, 0.4f, 0.6f});
  obj.style = VolumeStyle::xray;
  obj.transfer_function.points = {{0.0, glm::vec4(0)}, {2.0, glm::vec4(0.2f, 0.4f, 0.6f, 1.0f)}};
  PreparedVolume v(obj);
  Ray ray{{0, -100, 0}, {0, 1, 0}};
  VolumeHit hit;
  ASSERT_TRUE(project_volume(v, ray, 95.0, 97.0, 0.7, hit));
  EXPECT_NEAR(hit.t, 96.0, 1e-4);
  EXPECT_NEAR(hit.color.a, 0.75f, 1e-5f);           // two millimetres: 1 - 2^-2
  EXPECT_NEAR(hit.color.b, 0.75f * 0.3f, 1e-5f);    // the TF colour at value 1, premultiplied
  ASSERT_TRUE(project_volume(v, ray, 95.0, 98.0, 0.7, hit));
  EXPECT_NEAR(hit.color.a, 0.875f, 1e-5f);  // thicker shows darker: 1 - 2^-3
}

// A homogeneous cube clipped to z >= 4: a ray through the removed part sees nothing, a ray along
// z sees 6 mm of medium instead of 20.
TEST(VolumeStyles, ClipPlanesLimitWhatMdvrMarches) {
  VolumeObject obj = test::homogeneous_volume(0.2f, {1, 1, 1});
  obj.clip_planes.push_back({glm::dvec3(0, 0, 4), glm::dvec3(0, 0, 1)});
  std::vector<PreparedVolume> vols{PreparedVolume(obj)};
  MdvrParams p;
  p.step = 0.5f;
  p.ert = 1.0f;
  glm::vec4 removed = trace_mdvr(Ray{{0, -100, -2}, {0, 1, 0}}, {}, vols, {}, p);
  EXPECT_EQ(removed.a, 0.0f);
  glm::vec4 kept = trace_mdvr(Ray{{0, 0, -100}, {0, 0, 1}}, {}, vols, {}, p);
  EXPECT_NEAR(kept.a, 1.0 - std::pow(0.8, 6.0), 1e-4);
}

}  // namespace
}  // namespace imx
