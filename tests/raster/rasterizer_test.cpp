#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>

#include "core/blinn_phong.hpp"
#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "raster/rasterizer.hpp"
#include "raster_test_util.hpp"

namespace imx {
namespace {

using test::add_mesh;
using test::add_plane;
using test::FrameFragments;
using test::grid_offsets;
using test::make_scene;
using test::rasterize_frame;

struct DRay {
  glm::dvec3 origin, dir;
};

// The sample ray from the camera's definition, independent of CameraModel (default camera:
// eye (0,-600,0) looking along +y with +z up, so right = +x).
DRay analytic_ray(const Scene& scene, double px, double py) {
  const double w = scene.image.width, h = scene.image.height, aspect = w / h;
  const glm::dvec3 eye = scene.camera.eye, right{1, 0, 0}, up{0, 0, 1}, forward{0, 1, 0};
  if (scene.camera.projection == Projection::perspective) {
    double hh = std::tan(glm::radians(scene.camera.fov_deg) / 2.0);
    double sx = (2.0 * px / w - 1.0) * hh * aspect, sy = (1.0 - 2.0 * py / h) * hh;
    return {eye, glm::normalize(forward + sx * right + sy * up)};
  }
  double hh = scene.camera.ortho_height / 2.0;
  double sx = (2.0 * px / w - 1.0) * hh * aspect, sy = (1.0 - 2.0 * py / h) * hh;
  return {eye + sx * right + sy * up, forward};
}

// A square of half-size `half` centred at `c` spanning unit axes u and v; it faces u x v.
struct Square {
  glm::dvec3 c, u, v;
  double half;
  Mesh mesh() const {
    auto at = [&](double a, double b) { return glm::vec3(c + a * half * u + b * half * v); };
    return test::quad(at(-1, -1), at(1, -1), at(1, 1), at(-1, 1));
  }
  // Ray parameter and in-square coordinates (in mm) of the ray's hit with the square's plane.
  bool hit(const DRay& r, double& t, double& a, double& b) const {
    glm::dvec3 n = glm::cross(u, v);
    t = glm::dot(n, c - r.origin) / glm::dot(n, r.dir);
    glm::dvec3 p = r.origin + t * r.dir;
    a = glm::dot(p - c, u);
    b = glm::dot(p - c, v);
    return t > 0.0;
  }
};

// Checks that every sample well inside the square has exactly one fragment at the analytic
// depth, and every sample well outside none.
void expect_square_exact(Scene scene, const Square& sq, int tile_size) {
  add_mesh(scene, sq.mesh());
  CameraModel camera(scene.camera, scene.image.width, scene.image.height);
  Rasterizer r(scene, camera, {}, tile_size);
  EXPECT_EQ(r.triangle_count(), 2u);
  auto offsets = grid_offsets(4);
  FrameFragments f = rasterize_frame(r, camera, offsets);
  const double margin = 0.1;  // mm, far above the 1/256-pixel snapping
  int inside = 0, outside = 0;
  double worst = 0.0;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      for (int s = 0; s < f.spp; ++s) {
        DRay ray = analytic_ray(scene, x + offsets[s].x, y + offsets[s].y);
        double t, a, b;
        bool front = sq.hit(ray, t, a, b);
        double extent = std::max(std::abs(a), std::abs(b));
        const auto& frags = f.at(x, y, s);
        if (front && extent < sq.half - margin) {
          ASSERT_EQ(frags.size(), 1u) << x << "," << y << " sample " << s;
          worst = std::max(worst, std::abs(frags[0].t - t));
          ++inside;
        } else if (!front || extent > sq.half + margin) {
          ASSERT_EQ(frags.size(), 0u) << x << "," << y << " sample " << s;
          ++outside;
        }
      }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 1000);
  EXPECT_LT(worst, 1e-4) << "largest depth error in mm";
}

TEST(Rasterizer, PerspectiveQuadHasOneFragmentPerSampleAtTheExactDepth) {
  Scene scene = make_scene(80, 64);
  expect_square_exact(scene, {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 50.0}, 16);
  // Tilted, off-centre, and a tile size that does not divide the image.
  glm::dvec3 u = glm::normalize(glm::dvec3(1, 0.5, 0.2));
  glm::dvec3 v = glm::normalize(glm::dvec3(0, 0.3, 1) - glm::dot(glm::dvec3(0, 0.3, 1), u) * u);
  expect_square_exact(scene, {{10, 20, -5}, u, v, 60.0}, 24);
}

TEST(Rasterizer, OrthographicQuadDepthIsDistanceFromTheImagePlane) {
  Scene scene = make_scene(64, 80, Projection::orthographic);
  expect_square_exact(scene, {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 50.0}, 16);
  glm::dvec3 u = glm::normalize(glm::dvec3(1, 0.5, 0.2));
  glm::dvec3 v = glm::normalize(glm::dvec3(0, 0.3, 1) - glm::dot(glm::dvec3(0, 0.3, 1), u) * u);
  expect_square_exact(scene, {{10, 20, -5}, u, v, 60.0}, 32);
  // A quad at y = 0 seen head-on: every depth is exactly the eye-plane distance, 600 mm.
  CameraModel camera(scene.camera, 64, 80);
  Scene flat = make_scene(64, 80, Projection::orthographic);
  add_mesh(flat, Square{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 50.0}.mesh());
  Rasterizer r(flat, camera, {}, 16);
  FrameFragments f = rasterize_frame(r, camera, grid_offsets(2));
  const auto& centre = f.at(32, 40, 0);
  ASSERT_EQ(centre.size(), 1u);
  EXPECT_FLOAT_EQ(centre[0].t, 600.0f);
}

// Ray / box slab test in the box's own frame.
bool ray_box(const DRay& r, const glm::dmat3& rot, glm::dvec3 half, double& t0, double& t1) {
  glm::dmat3 inv = glm::transpose(rot);
  glm::dvec3 o = inv * r.origin, d = inv * r.dir;
  t0 = -1e300, t1 = 1e300;
  for (int a = 0; a < 3; ++a) {
    double ta = (-half[a] - o[a]) / d[a], tb = (half[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t1 >= t0 && t0 > 0.0;
}

void expect_closed_box(Projection projection) {
  Scene scene = make_scene(72, 64, projection);
  const glm::dvec3 half{40, 30, 50};
  glm::dmat3 rot = glm::dmat3(glm::rotate(glm::dmat4(1.0), 0.5, glm::dvec3(0.3, 0.8, 0.4)));
  Mesh m = test::box(-glm::vec3(half), glm::vec3(half));
  for (glm::vec3& p : m.positions) p = glm::vec3(rot * glm::dvec3(p));
  add_mesh(scene, m);
  CameraModel camera(scene.camera, 72, 64);
  Rasterizer r(scene, camera, {}, 16);
  auto offsets = grid_offsets(4);
  FrameFragments f = rasterize_frame(r, camera, offsets);
  int inside = 0, outside = 0;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      for (int s = 0; s < f.spp; ++s) {
        const auto& frags = f.at(x, y, s);
        ASSERT_EQ(frags.size() % 2, 0u) << x << "," << y << " sample " << s;
        DRay ray = analytic_ray(scene, x + offsets[s].x, y + offsets[s].y);
        double t0, t1;
        if (ray_box(ray, rot, half - 0.2, t0, t1)) {
          ASSERT_EQ(frags.size(), 2u);
          EXPECT_EQ(frags[0].front_facing, 1u);
          EXPECT_EQ(frags[1].front_facing, 0u);
          ray_box(ray, rot, half, t0, t1);
          EXPECT_NEAR(frags[0].t, t0, 1e-4);
          EXPECT_NEAR(frags[1].t, t1, 1e-4);
          ++inside;
        } else if (!ray_box(ray, rot, half + 0.2, t0, t1)) {
          ASSERT_EQ(frags.size(), 0u);
          ++outside;
        }
      }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 1000);
}

TEST(Rasterizer, ClosedBoxGivesTwoFragmentsInsideItsSilhouetteAndEvenCountsEverywhere) {
  expect_closed_box(Projection::perspective);
  expect_closed_box(Projection::orthographic);
}

TEST(Rasterizer, ClosedSphereIsWatertightAtEverySample) {
  for (Projection projection : {Projection::perspective, Projection::orthographic}) {
    Scene scene = make_scene(96, 96, projection);
    add_mesh(scene, test::sphere({3, 10, -2}, 70.0f, 48, 96));
    CameraModel camera(scene.camera, 96, 96);
    Rasterizer r(scene, camera, {}, 32);
    auto offsets = grid_offsets(4);
    FrameFragments f = rasterize_frame(r, camera, offsets);
    size_t two = 0;
    for (const auto& frags : f.samples) {
      ASSERT_EQ(frags.size() % 2, 0u);
      two += frags.size() == 2 ? 1 : 0;
    }
    EXPECT_GT(two, 10000u);
    EXPECT_EQ(f.at(48, 48, 0).size(), 2u);
  }
}

// One millimetre per pixel: image x = 32 + world x, image y = 32 - world z.
Scene pixel_exact_scene() {
  Scene scene = make_scene(64, 64, Projection::orthographic);
  scene.camera.ortho_height = 64.0;
  return scene;
}

glm::vec3 at_pixel(double px, double py) {
  return {float(px - 32.0), 0.0f, float(32.0 - py)};
}

TEST(Rasterizer, SamplesOnSharedEdgesAndVerticesAreCountedExactlyOnce) {
  // A 2x2 grid of quads (8 triangles, both diagonal directions) with every edge and the inner
  // vertex passing exactly through sample positions.
  Scene scene = pixel_exact_scene();
  Mesh m;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) m.positions.push_back(at_pixel(8 + 12 * i, 8 + 12 * j));
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      unsigned a = j * 3 + i, b = a + 1, c = a + 4, d = a + 3;
      if ((i + j) % 2 == 0) {
        m.triangles.push_back({a, b, c});
        m.triangles.push_back({a, c, d});
      } else {
        m.triangles.push_back({b, c, d});
        m.triangles.push_back({b, d, a});
      }
    }
  add_mesh(scene, m);
  CameraModel camera(scene.camera, 64, 64);
  Rasterizer r(scene, camera, {}, 16);
  std::vector<glm::vec2> offsets;
  for (float oy : {0.0f, 0.25f, 0.5f, 0.75f})
    for (float ox : {0.0f, 0.25f, 0.5f, 0.75f}) offsets.emplace_back(ox, oy);
  FrameFragments f = rasterize_frame(r, camera, offsets);
  int on_diagonal = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      for (int s = 0; s < f.spp; ++s) {
        double px = x + offsets[s].x, py = y + offsets[s].y;
        bool interior = px > 8 && px < 32 && py > 8 && py < 32;
        bool exterior = px < 8 || px > 32 || py < 8 || py > 32;
        size_t n = f.at(x, y, s).size();
        if (interior) {
          EXPECT_EQ(n, 1u) << px << ", " << py;
        }
        if (exterior) {
          EXPECT_EQ(n, 0u) << px << ", " << py;
        }
        double lx = std::fmod(px - 8, 12.0), ly = std::fmod(py - 8, 12.0);
        if (interior && (lx == ly || lx + ly == 12.0 || lx == 0.0 || ly == 0.0)) ++on_diagonal;
      }
  EXPECT_GT(on_diagonal, 100);  // the test really put samples on the shared edges
}

TEST(Rasterizer, PerspectiveQuadDiagonalThroughTheImageCentreIsCountedOnce) {
  Scene scene = make_scene(64, 64);
  add_mesh(scene, Square{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 50.0}.mesh());
  CameraModel camera(scene.camera, 64, 64);
  Rasterizer r(scene, camera, {}, 16);
  // Samples on the projected diagonal px - 32 = -(py - 32), including the image centre.
  for (int k = -8; k < 8; ++k)
    for (float o : {0.0f, 0.125f, 0.5f, 0.875f}) {
      int x = 32 + k, y = 31 - k;
      glm::vec2 offset(o, 1.0f - o);
      if (o == 0.0f) offset = {0.0f, 0.0f}, y = 32 - k;  // exactly (32 + k, 32 - k)
      SampleFragments out;
      TileRect tile{x / 16 * 16, y / 16 * 16, x / 16 * 16 + 16, y / 16 * 16 + 16};
      r.rasterize(tile, std::span(&offset, 1), out);
      size_t index = static_cast<size_t>(y - tile.y0) * 16 + (x - tile.x0);
      EXPECT_EQ(out.of(index).size(), 1u) << x + offset.x << ", " << y + offset.y;
    }
}

// Ray / triangle intersection (Moller-Trumbore) in double with the smallest barycentric.
bool ray_triangle(const DRay& r, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, double& t,
                  double& min_bary) {
  glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(r.dir, e2);
  double det = glm::dot(e1, p);
  glm::dvec3 s = r.origin - a;
  double u = glm::dot(s, p) / det;
  glm::dvec3 q = glm::cross(s, e1);
  double v = glm::dot(r.dir, q) / det;
  t = glm::dot(e2, q) / det;
  min_bary = std::min({u, v, 1.0 - u - v});
  return true;
}

TEST(Rasterizer, TriangleCrossingTheEyePlaneIsClippedCleanly) {
  Scene scene = make_scene(64, 64);
  // Camera-space depths -100, -100 and 150: the triangle passes beside and behind the eye.
  glm::dvec3 a{-80, -700, -30}, b{80, -700, -30}, c{0, -450, 40};
  Mesh m;
  m.positions = {glm::vec3(a), glm::vec3(b), glm::vec3(c)};
  m.triangles = {{0, 1, 2}};
  add_mesh(scene, m);
  CameraModel camera(scene.camera, 64, 64);
  Rasterizer r(scene, camera, {}, 16);
  EXPECT_GE(r.triangle_count(), 1u);
  auto offsets = grid_offsets(4);
  FrameFragments f = rasterize_frame(r, camera, offsets);
  int hits = 0, misses = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      for (int s = 0; s < f.spp; ++s) {
        const auto& frags = f.at(x, y, s);
        for (const Fragment& fr : frags) {
          EXPECT_TRUE(std::isfinite(fr.t));
          EXPECT_GT(fr.t, 0.0f);
        }
        DRay ray = analytic_ray(scene, x + offsets[s].x, y + offsets[s].y);
        double t, min_bary;
        ray_triangle(ray, a, b, c, t, min_bary);
        if (t > 1.0 && min_bary > 1e-3) {
          ASSERT_EQ(frags.size(), 1u);
          EXPECT_NEAR(frags[0].t, t, 1e-3);
          ++hits;
        } else if (t < 0.0 || min_bary < -1e-3) {
          ASSERT_EQ(frags.size(), 0u);
          ++misses;
        }
      }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(misses, 300);

  // Entirely behind the eye: nothing at all.
  Scene behind = make_scene(64, 64);
  Mesh back;
  back.positions = {{-80, -700, -30}, {80, -700, -30}, {0, -650, 40}};
  back.triangles = {{0, 1, 2}};
  add_mesh(behind, back);
  Rasterizer rb(behind, camera, {}, 16);
  EXPECT_EQ(rb.triangle_count(), 0u);
  FrameFragments fb = rasterize_frame(rb, camera, offsets);
  for (const auto& frags : fb.samples) EXPECT_TRUE(frags.empty());
}

void expect_point_lands_on_its_pixel(Projection projection, glm::dvec3 point, glm::dvec2 expected) {
  Scene scene = make_scene(100, 80, projection);
  CameraModel camera(scene.camera, 100, 80);
  glm::dvec2 p = camera.project(point);
  EXPECT_NEAR(p.x, expected.x, 1e-9);
  EXPECT_NEAR(p.y, expected.y, 1e-9);
  // A small triangle around the point covers the sample exactly at the point's projection.
  Mesh m;
  m.positions = {glm::vec3(point + glm::dvec3(-4, 0, -3)), glm::vec3(point + glm::dvec3(4, 0, -3)),
                 glm::vec3(point + glm::dvec3(0, 0, 5))};
  m.triangles = {{0, 1, 2}};
  add_mesh(scene, m);
  Rasterizer r(scene, camera, {}, 20);
  glm::vec2 offset(static_cast<float>(p.x - std::floor(p.x)),
                   static_cast<float>(p.y - std::floor(p.y)));
  FrameFragments f = rasterize_frame(r, camera, std::span(&offset, 1));
  int px = static_cast<int>(std::floor(p.x)), py = static_cast<int>(std::floor(p.y));
  ASSERT_EQ(f.at(px, py, 0).size(), 1u);
  double depth = camera.depth_of(camera.to_camera(point));
  EXPECT_NEAR(f.at(px, py, 0)[0].t, depth, 1e-3);
  EXPECT_TRUE(f.at(px + 8, py, 0).empty());
  EXPECT_TRUE(f.at(px, py - 8, 0).empty());
}

TEST(Rasterizer, KnownWorldPointsProjectToKnownPixels) {
  const double tan15 = std::tan(glm::radians(15.0));
  // Perspective: the target at the centre; (30, 0, -20) at 600 mm from the eye.
  expect_point_lands_on_its_pixel(Projection::perspective, {0, 0, 0}, {50, 40});
  expect_point_lands_on_its_pixel(
      Projection::perspective, {30, 0, -20},
      {50 + 30.0 / (600 * tan15 * 1.25) * 50, 40 + 20.0 / (600 * tan15) * 40});
  // Further away: (30, 300, 10) at 900 mm.
  expect_point_lands_on_its_pixel(
      Projection::perspective, {30, 300, 10},
      {50 + 30.0 / (900 * tan15 * 1.25) * 50, 40 - 10.0 / (900 * tan15) * 40});
  // Orthographic, 200 mm high: 0.4 px per mm, independent of depth.
  expect_point_lands_on_its_pixel(Projection::orthographic, {0, 0, 0}, {50, 40});
  expect_point_lands_on_its_pixel(Projection::orthographic, {30, 250, -20},
                                  {50 + 30 * 0.4, 40 + 20 * 0.4});
}

TEST(Rasterizer, FrontFacingFollowsTheGeometricNormal) {
  for (Projection projection : {Projection::perspective, Projection::orthographic}) {
    Scene scene = make_scene(32, 32, projection);
    Square facing{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 50.0};  // normal -y, toward the eye
    Square away{{0, 100, 0}, {0, 0, 1}, {1, 0, 0}, 50.0};  // normal +y
    add_mesh(scene, facing.mesh());
    add_mesh(scene, away.mesh());
    CameraModel camera(scene.camera, 32, 32);
    Rasterizer r(scene, camera, {}, 16);
    FrameFragments f = rasterize_frame(r, camera, grid_offsets(1));
    const auto& frags = f.at(16, 16, 0);
    ASSERT_EQ(frags.size(), 2u);
    EXPECT_EQ(frags[0].object, 0u);
    EXPECT_EQ(frags[0].front_facing, 1u);
    EXPECT_EQ(frags[1].object, 1u);
    EXPECT_EQ(frags[1].front_facing, 0u);
  }
}

TEST(Rasterizer, MprPlaneShowsTheWindowedVolumeValueAndNothingOutsideTheGrid) {
  // 8^3 voxels, 2 mm apart, centred at the origin; value = 10 i + 3 j + k (exactly trilinear).
  auto data = std::make_shared<VolumeData>();
  data->dims = {8, 8, 8};
  std::vector<float> voxels;
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i) voxels.push_back(10.0f * i + 3.0f * j + k);
  data->voxels = voxels;
  data->index_to_world = glm::translate(glm::dmat4(1.0), glm::dvec3(-7.0)) *
                         glm::scale(glm::dmat4(1.0), glm::dvec3(2.0));
  Scene scene = pixel_exact_scene();
  VolumeObject vo;
  vo.name = "ct";
  vo.data = data;
  vo.index_to_world = data->index_to_world;
  vo.transfer_function.points = {{0.0, glm::vec4(0.0f)}, {100.0, glm::vec4(1.0f)}};
  scene.volumes.push_back(vo);
  scene.order.push_back({ObjectKind::volume, 0});
  PlaneObject plane;
  plane.name = "coronal";
  plane.center = {0, 2, 0};  // j = 4.5
  plane.normal = {0, -1, 0};
  plane.up = {0, 0, 1};
  plane.size = {100, 100};
  plane.volume = 0;
  plane.window = {40.0, 100.0};
  plane.color = {1.0f, 0.5f, 0.25f};
  plane.opacity = 0.8f;
  add_plane(scene, plane);
  std::vector<PreparedVolume> volumes;
  volumes.emplace_back(scene.volumes[0]);
  CameraModel camera(scene.camera, 64, 64);
  Rasterizer r(scene, camera, volumes, 16);
  auto offsets = grid_offsets(2);
  FrameFragments f = rasterize_frame(r, camera, offsets);
  int inside = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      for (int s = 0; s < f.spp; ++s) {
        double wx = x + offsets[s].x - 32.0, wz = 32.0 - (y + offsets[s].y);
        const auto& frags = f.at(x, y, s);
        if (std::abs(wx) < 6.9 && std::abs(wz) < 6.9) {
          ASSERT_EQ(frags.size(), 1u);
          double value = 10.0 * (wx + 7.0) / 2.0 + 3.0 * 4.5 + (wz + 7.0) / 2.0;
          // The window's display grey, decoded (docs/colour.md).
          double grey = srgb_decode(
              static_cast<float>(std::clamp((value - (40.0 - 50.0)) / 100.0, 0.0, 1.0)));
          EXPECT_NEAR(frags[0].color.r, grey * 1.0 * 0.8, 1e-4);
          EXPECT_NEAR(frags[0].color.g, grey * 0.5 * 0.8, 1e-4);
          EXPECT_NEAR(frags[0].color.b, grey * 0.25 * 0.8, 1e-4);
          EXPECT_FLOAT_EQ(frags[0].color.a, 0.8f);
          EXPECT_EQ(frags[0].object, 1u);  // order: the volume, then the plane
          EXPECT_NEAR(frags[0].t, 602.0, 1e-4);
          ++inside;
        } else if (std::abs(wx) > 7.1 || std::abs(wz) > 7.1) {
          ASSERT_EQ(frags.size(), 0u);
        }
      }
  EXPECT_GT(inside, 500);

  // Without a volume the plane is its colour over its whole rectangle (width along x here).
  Scene bare = pixel_exact_scene();
  plane.volume = -1;
  plane.size = {20, 10};
  add_plane(bare, plane);
  Rasterizer rb(bare, camera, {}, 16);
  FrameFragments fb = rasterize_frame(rb, camera, grid_offsets(1));
  ASSERT_EQ(fb.at(32 + 9, 32, 0).size(), 1u);
  EXPECT_TRUE(fb.at(32, 32 - 6, 0).empty());
  EXPECT_TRUE(fb.at(32 + 11, 32, 0).empty());
  const Fragment& g = fb.at(32, 32, 0)[0];
  EXPECT_FLOAT_EQ(g.color.r, 0.8f);
  EXPECT_FLOAT_EQ(g.color.g, 0.4f);
  EXPECT_FLOAT_EQ(g.color.b, 0.2f);
  EXPECT_FLOAT_EQ(g.color.a, 0.8f);
  EXPECT_EQ(g.front_facing, 1u);
}

TEST(Rasterizer, MeshShadingUsesInterpolatedVertexNormalsAndPremultiplies) {
  Scene scene = make_scene(48, 48);
  Mesh m = Square{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 120.0}.mesh();
  // Vertex normals tilted to the left and the right: the shade varies across the quad.
  m.normals = {glm::normalize(glm::vec3(-0.6f, -1, 0)), glm::normalize(glm::vec3(0.6f, -1, 0)),
               glm::normalize(glm::vec3(0.6f, -1, 0)), glm::normalize(glm::vec3(-0.6f, -1, 0))};
  Material material;
  material.color = {0.9f, 0.6f, 0.3f};
  material.opacity = 0.5f;
  material.shading = {true, 0.1f, 0.6f, 0.4f, 8.0f};
  add_mesh(scene, m, material);
  CameraModel camera(scene.camera, 48, 48);
  Rasterizer r(scene, camera, {}, 16);
  FrameFragments f = rasterize_frame(r, camera, grid_offsets(1));
  ShadingLight head = resolve_light(scene.lights[0]);
  for (int x : {12, 20, 24, 30, 36}) {
    const int y = 22;
    const auto& frags = f.at(x, y, 0);
    ASSERT_EQ(frags.size(), 1u);
    Ray ray = camera.ray(x + 0.5, y + 0.5);
    glm::vec3 hit = ray.at(frags[0].t);
    float w = (hit.x + 120.0f) / 240.0f;  // 0 on the left edge, 1 on the right
    glm::vec3 n = (1 - w) * m.normals[0] + w * m.normals[1];
    glm::vec3 rgb = blinn_phong(material.shading, material.color, n, -ray.dir, std::span(&head, 1));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(frags[0].color[c], rgb[c] * 0.5f, 1e-4f) << x;
    EXPECT_FLOAT_EQ(frags[0].color.a, 0.5f);
  }
  EXPECT_GT(std::abs(f.at(12, 22, 0)[0].color.r - f.at(36, 22, 0)[0].color.r), 1e-3f);
}

Scene busy_scene() {
  Scene scene = make_scene(100, 70);
  scene.volumes.emplace_back();  // order holds a volume first: ids must skip it
  scene.order.push_back({ObjectKind::volume, 0});
  add_mesh(scene, test::sphere({0, 0, 0}, 60.0f, 24, 48));
  Material glass;
  glass.opacity = 0.3f;
  add_mesh(scene, test::box({-30, -80, -30}, {40, 50, 20}), glass);
  PlaneObject p;
  p.normal = glm::normalize(glm::dvec3(0.2, -1, 0.3));
  p.size = {150, 120};
  add_plane(scene, p);
  return scene;
}

TEST(Rasterizer, OutputIsSortedDeterministicAndIndependentOfThreads) {
  Scene scene = busy_scene();
  CameraModel camera(scene.camera, 100, 70);
  Rasterizer r(scene, camera, {}, 16);
  auto offsets = grid_offsets(3);
  FrameFragments serial = rasterize_frame(r, camera, offsets);
  size_t layered = 0;
  for (const auto& frags : serial.samples) {
    for (size_t i = 1; i < frags.size(); ++i) ASSERT_LE(frags[i - 1].t, frags[i].t);
    layered += frags.size() >= 4 ? 1 : 0;
  }
  EXPECT_GT(layered, 1000u);

  // Same tile twice into a reused buffer: identical bytes.
  TileRect tile{48, 32, 64, 48};
  SampleFragments a, b;
  r.rasterize(tile, offsets, a);
  r.rasterize({0, 0, 16, 16}, offsets, b);
  r.rasterize(tile, offsets, b);
  ASSERT_EQ(a.offsets, b.offsets);
  ASSERT_EQ(a.fragments.size(), b.fragments.size());
  EXPECT_EQ(
      std::memcmp(a.fragments.data(), b.fragments.data(), a.fragments.size() * sizeof(Fragment)),
      0);

  // Many threads, each tile once: identical to the serial frame.
  std::vector<SampleFragments> tiles((100 / 16 + 1) * (70 / 16 + 1));
  for_each_tile(100, 70, 16, 4,
                [&](const TileRect& t, int index) { r.rasterize(t, offsets, tiles[index]); });
  int tiles_x = (100 + 15) / 16;
  for (int index = 0; index < static_cast<int>(tiles.size()); ++index) {
    int tx = index % tiles_x, ty = index / tiles_x;
    TileRect t{tx * 16, ty * 16, std::min(100, tx * 16 + 16), std::min(70, ty * 16 + 16)};
    size_t i = 0;
    for (int y = t.y0; y < t.y1; ++y)
      for (int x = t.x0; x < t.x1; ++x)
        for (int s = 0; s < serial.spp; ++s, ++i) {
          auto got = tiles[index].of(i);
          const auto& want = serial.at(x, y, s);
          ASSERT_EQ(got.size(), want.size());
          for (size_t k = 0; k < got.size(); ++k) {
            EXPECT_EQ(got[k].t, want[k].t);
            EXPECT_EQ(got[k].object, want[k].object);
            EXPECT_EQ(got[k].color, want[k].color);
          }
        }
  }
}

TEST(Rasterizer, EqualDepthsKeepSceneOrder) {
  Scene scene = make_scene(32, 32);
  Square sq{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 50.0};
  Material red, green, blue;
  red.color = {1, 0, 0};
  green.color = {0, 1, 0};
  blue.color = {0, 0, 1};
  add_mesh(scene, Square{{0, 50, 0}, {1, 0, 0}, {0, 0, 1}, 50.0}.mesh(), red);  // behind
  add_mesh(scene, sq.mesh(), green);
  add_mesh(scene, sq.mesh(), blue);  // coplanar with green
  CameraModel camera(scene.camera, 32, 32);
  Rasterizer r(scene, camera, {}, 16);
  FrameFragments f = rasterize_frame(r, camera, grid_offsets(2));
  for (int y = 12; y < 20; ++y)
    for (int x = 12; x < 20; ++x) {
      const auto& frags = f.at(x, y, 1);
      ASSERT_EQ(frags.size(), 3u);
      EXPECT_EQ(frags[0].t, frags[1].t);
      EXPECT_EQ(frags[0].object, 1u);
      EXPECT_EQ(frags[1].object, 2u);
      EXPECT_EQ(frags[2].object, 0u);
    }
}

TEST(Rasterizer, ManyLayersAreSortedStably) {
  // 48 quads (more than the insertion-sort limit) in scrambled depth order, in pairs of equal
  // depth: rows come out sorted by t, equal depths in scene order.
  Scene scene = make_scene(32, 32, Projection::orthographic);
  for (int i = 0; i < 48; ++i) {
    double y = ((i / 2) * 7 % 24) * 10.0;
    add_mesh(scene, Square{{0, y, 0}, {1, 0, 0}, {0, 0, 1}, 150.0}.mesh());
  }
  CameraModel camera(scene.camera, 32, 32);
  Rasterizer r(scene, camera, {}, 16);
  FrameFragments f = rasterize_frame(r, camera, grid_offsets(2));
  for (const auto& frags : f.samples) {
    ASSERT_EQ(frags.size(), 48u);
    for (size_t i = 1; i < frags.size(); ++i) {
      ASSERT_LE(frags[i - 1].t, frags[i].t);
      if (frags[i - 1].t == frags[i].t) {
        ASSERT_LT(frags[i - 1].object, frags[i].object);
      }
    }
    EXPECT_FLOAT_EQ(frags.front().t, 600.0f);
    EXPECT_FLOAT_EQ(frags.back().t, 830.0f);
  }
}

// Clip geometry (SPEC §7): a clip mesh of opacity 0 only cuts, so the ordinary rows leave it out;
// the clip rows hold the clip meshes alone, unshaded, with Scene::order ids either way.
TEST(Rasterizer, ClipMeshesHaveRowsOfTheirOwn) {
  Scene scene = make_scene(32, 32);
  VolumeObject v;  // only its clip list matters here
  v.name = "ct";
  scene.order.push_back({ObjectKind::volume, 0});
  scene.volumes.push_back(v);
  Material hidden;
  hidden.opacity = 0.0f;
  add_mesh(scene, test::box({-30, -30, -30}, {30, 30, 30}), hidden, "cutter");     // order 1
  add_mesh(scene, test::box({-10, -80, -10}, {10, -60, 10}), {}, "drawn");         // order 2
  add_mesh(scene, test::box({-50, -50, -50}, {50, -40, 50}), {}, "shown cutter");  // order 3
  scene.volumes[0].clip_meshes = {{0, false}, {2, true}};
  CameraModel camera(scene.camera, scene.image.width, scene.image.height);
  const auto offsets = grid_offsets(1);
  FrameFragments shown = rasterize_frame(Rasterizer(scene, camera, {}, 16), camera, offsets);
  FrameFragments clip =
      rasterize_frame(Rasterizer(scene, camera, {}, 16, RasterObjects::clip), camera, offsets);
  const std::vector<Fragment>& a = shown.at(16, 16, 0);
  const std::vector<Fragment>& b = clip.at(16, 16, 0);
  ASSERT_EQ(a.size(), 4u);  // "drawn" and "shown cutter", front and back
  ASSERT_EQ(b.size(), 4u);  // "cutter" and "shown cutter"
  for (const Fragment& f : a) EXPECT_TRUE(f.object == 2u || f.object == 3u) << f.object;
  for (const Fragment& f : b) {
    EXPECT_TRUE(f.object == 1u || f.object == 3u) << f.object;
    EXPECT_EQ(f.color, glm::vec4(0.0f));
  }
  EXPECT_EQ(b.front().object, 3u);
  EXPECT_EQ(b.front().front_facing, 1u);
  EXPECT_EQ(b.back().object, 1u);
  EXPECT_EQ(b.back().front_facing, 0u);
  EXPECT_EQ(shown_meshes(scene), (std::vector<bool>{false, true, true}));
}

TEST(Rasterizer, ReportsBadInputNamingTheCulprit) {
  CameraModel camera(Camera{}, 32, 32);
  auto message = [&](const Scene& scene, std::span<const PreparedVolume> volumes = {}) {
    try {
      Rasterizer r(scene, camera, volumes, 16);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  Scene s = make_scene(32, 32);
  Mesh bad = test::quad({0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1});
  bad.triangles.push_back({0, 1, 7});
  add_mesh(s, bad, {}, "implant");
  EXPECT_NE(message(s).find("implant"), std::string::npos);

  Scene missing = make_scene(32, 32);
  add_mesh(missing, test::box({0, 0, 0}, {1, 1, 1}), {}, "lost");
  missing.order.clear();
  EXPECT_NE(message(missing).find("lost"), std::string::npos);

  Scene plane = make_scene(32, 32);
  PlaneObject p;
  p.name = "axial";
  p.normal = {0, 0, 0};
  add_plane(plane, p);
  EXPECT_NE(message(plane).find("axial"), std::string::npos);
  plane.planes[0].normal = {0, 1, 0};
  plane.planes[0].up = {0, 2, 0};
  EXPECT_NE(message(plane).find("up"), std::string::npos);
  plane.planes[0].up = {0, 0, 1};
  plane.planes[0].volume = 3;
  EXPECT_NE(message(plane).find("volume index 3"), std::string::npos);

  Scene ok = make_scene(32, 32);
  Rasterizer r(ok, camera, {}, 16);
  SampleFragments out;
  glm::vec2 inside(0.5f), outside(1.5f, 0.5f);
  EXPECT_THROW(r.rasterize({8, 0, 24, 16}, std::span(&inside, 1), out), Error);
  EXPECT_THROW(r.rasterize({0, 0, 16, 16}, std::span(&outside, 1), out), Error);
  EXPECT_THROW(Rasterizer(ok, camera, {}, 0), Error);
  r.rasterize({16, 16, 32, 32}, std::span(&inside, 1), out);
  EXPECT_EQ(out.sample_count(), 256u);
  EXPECT_TRUE(out.fragments.empty());
}

}  // namespace
}  // namespace imx
