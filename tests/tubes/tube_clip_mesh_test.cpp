// Clip meshes on tubes: a closed mesh keeps the tubes inside it (probing) or outside it
// (cutting), a flat cap lies where the mesh's surface cuts a tube (on the surface, in the tube's
// colour there, facing out of the kept side), and windings count from the ray's start.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "tube_rod.hpp"
#include "tubes/tube_clip_meshes.hpp"
#include "tubes/tube_fragments.hpp"
#include "tubes/tube_geometry.hpp"

namespace imx {
namespace {

// The grey the rod has at x (value x over [-10, 10]), linear: the grey map gives display greys
// (docs/colour.md).
float grey_at(float x) {
  return srgb_decode((x + 10.0f) / 20.0f);
}

// Turns every triangle of a mesh that is convex around `centre` to face away from it.
void wind_outward(Mesh& m, const glm::vec3& centre) {
  for (glm::uvec3& t : m.triangles) {
    const glm::vec3 a = m.positions[t.x], b = m.positions[t.y], c = m.positions[t.z];
    if (glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0f - centre) < 0.0f) std::swap(t.y, t.z);
  }
}

// An axis-aligned box from `low` to `high`, 12 triangles.
Mesh box(const glm::vec3& low, const glm::vec3& high) {
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.push_back({i & 1 ? high.x : low.x, i & 2 ? high.y : low.y, i & 4 ? high.z : low.z});
  const std::array<std::array<uint32_t, 4>, 6> faces = {
      {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}}};
  for (const auto& f : faces) {
    m.triangles.push_back({f[0], f[1], f[2]});
    m.triangles.push_back({f[0], f[2], f[3]});
  }
  wind_outward(m, (low + high) * 0.5f);
  return m;
}

// An icosphere: the icosahedron subdivided `levels` times, vertices on the sphere.
Mesh icosphere(const glm::vec3& centre, float radius, int levels) {
  const float g = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<glm::vec3> p = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                              {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                              {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (glm::vec3& v : p) v = glm::normalize(v);
  std::vector<glm::uvec3> tris = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                  {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                  {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                  {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> middle;
    auto mid = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto [it, fresh] = middle.try_emplace(key, static_cast<uint32_t>(p.size()));
      if (fresh) p.push_back(glm::normalize(p[a] + p[b]));
      return it->second;
    };
    std::vector<glm::uvec3> next;
    for (const glm::uvec3& t : tris) {
      const uint32_t ab = mid(t.x, t.y), bc = mid(t.y, t.z), ca = mid(t.z, t.x);
      next.insert(next.end(), {{t.x, ab, ca}, {t.y, bc, ab}, {t.z, ca, bc}, {ab, bc, ca}});
    }
    tris = std::move(next);
  }
  Mesh m;
  for (const glm::vec3& v : p) m.positions.push_back(centre + radius * v);
  m.triangles = std::move(tris);
  wind_outward(m, centre);
  return m;
}

std::vector<MeshObject> objects_of(std::vector<Mesh> meshes) {
  std::vector<MeshObject> out;
  for (Mesh& m : meshes) {
    out.emplace_back();
    out.back().mesh = std::make_shared<const Mesh>(std::move(m));
  }
  return out;
}

std::vector<Fragment> fragments(const StreamlineObject& o, const std::vector<MeshObject>& meshes,
                                const Ray& ray) {
  const TubeGeometry tubes(o);
  const TubeLook look = make_tube_look(o, tubes, meshes);
  std::vector<Fragment> out;
  append_tube_fragments(look, ray, 1e9f, 0, {}, out);
  return out;
}

// Looking along +x, exactly along the rod's axis.
const glm::vec3 kAlongX(1.0f, 0.0f, 0.0f);

TEST(TubeClipMesh, ProbingKeepsOnlyTheTubesInside) {
  StreamlineObject o = test::rod(0.5, 1.0f);
  o.clip_meshes.push_back({0, true});
  const auto meshes = objects_of({box({-4, -3, -3}, {4, 3, 3})});
  for (float x : {-9.0f, -5.0f, -4.2f, 4.2f, 7.0f})
    EXPECT_TRUE(fragments(o, meshes, Ray{{x, 0.1f, -20.0f}, {0, 0, 1}}).empty()) << x;
  for (float x : {-3.8f, 0.0f, 2.5f}) {
    const auto out = fragments(o, meshes, Ray{{x, 0.1f, -20.0f}, {0, 0, 1}});
    ASSERT_EQ(out.size(), 1u) << x;
    EXPECT_NEAR(out[0].t, 20.0f - std::sqrt(0.25f - 0.01f), 1e-4f) << x;
  }
}

TEST(TubeClipMesh, CuttingKeepsOnlyTheTubesOutside) {
  StreamlineObject o = test::rod(0.5, 1.0f);
  o.clip_meshes.push_back({0, false});
  const auto meshes = objects_of({box({-4, -3, -3}, {4, 3, 3})});
  for (float x : {-3.8f, 0.0f, 2.5f})
    EXPECT_TRUE(fragments(o, meshes, Ray{{x, 0.1f, -20.0f}, {0, 0, 1}}).empty()) << x;
  for (float x : {-9.0f, -5.0f, 4.2f, 7.0f})
    EXPECT_EQ(fragments(o, meshes, Ray{{x, 0.1f, -20.0f}, {0, 0, 1}}).size(), 1u) << x;
}

TEST(TubeClipMesh, TheCutIsCappedOnTheMeshInTheTubesColourThere) {
  for (float opacity : {1.0f, 0.4f}) {
    StreamlineObject o = test::rod(0.5, opacity);
    o.clip_meshes.push_back({0, true});
    const auto meshes = objects_of({box({-4, -3, -3}, {4, 3, 3})});
    const float a = tube_fragment_alpha(opacity);
    for (float y : {0.0f, 0.3f, -0.4f}) {
      const Ray ray{{-30.0f, y, 0.1f}, kAlongX};
      const auto out = fragments(o, meshes, ray);
      ASSERT_FALSE(out.empty()) << y;
      EXPECT_NEAR(out[0].t, 26.0f / kAlongX.x, 1e-4f) << y;  // the box's face x = -4
      EXPECT_EQ(out[0].front_facing, 1u);
      EXPECT_NEAR(out[0].color.a, a, 1e-6f);
      EXPECT_NEAR(out[0].color.r, grey_at(-4.0f) * a, 2e-3f);
      if (opacity < 1.0f) {  // and a cap where the ray leaves the box, facing away
        ASSERT_EQ(out.size(), 2u) << y;
        EXPECT_NEAR(out[1].t, 34.0f / kAlongX.x, 1e-4f);
        EXPECT_EQ(out[1].front_facing, 0u);
        EXPECT_NEAR(out[1].color.r, grey_at(4.0f) * a, 2e-3f);
      } else {
        EXPECT_EQ(out.size(), 1u);
      }
    }
    // Without the clip mesh no cap: the rod's own round end at x = -10 comes first.
    StreamlineObject whole = test::rod(0.5, opacity);
    const auto out = fragments(whole, {}, Ray{{-30.0f, 0.1f, 0.1f}, kAlongX});
    ASSERT_FALSE(out.empty());
    EXPECT_LT(out[0].t, 20.5f / kAlongX.x);
    // Beside the tube, the mesh's surface shows nothing.
    EXPECT_TRUE(fragments(o, meshes, Ray{{-30.0f, 0.6f, 0.0f}, kAlongX}).empty());
  }
}

TEST(TubeClipMesh, ACapOnASphereLiesOnItsSurfaceFacingOutOfTheKeptSide) {
  const float r = 5.0f;
  const auto meshes = objects_of({icosphere({0, 0, 0}, r, 4)});
  for (bool keep_inside : {true, false}) {
    StreamlineObject o = test::rod(0.6, 0.5f);
    o.clip_meshes.push_back({0, keep_inside});
    for (float y : {0.0f, 0.25f, -0.45f}) {
      const Ray ray{{-30.0f, y, 0.05f}, kAlongX};
      const auto out = fragments(o, meshes, ray);
      // Where the ray meets the sphere: |origin + t dir| = r.
      const float b = glm::dot(ray.origin, ray.dir);
      const float c = glm::dot(ray.origin, ray.origin) - r * r;
      const float enter = -b - std::sqrt(b * b - c), leave = -b + std::sqrt(b * b - c);
      const float a = tube_fragment_alpha(0.5f);
      if (keep_inside) {  // a cap entering, one leaving, nothing else
        ASSERT_EQ(out.size(), 2u) << y;
        EXPECT_NEAR(out[0].t, enter, 0.02f) << y;  // the icosphere lies within 0.01 of the sphere
        EXPECT_NEAR(out[1].t, leave, 0.02f) << y;
        EXPECT_EQ(out[0].front_facing, 1u);
        EXPECT_EQ(out[1].front_facing, 0u);
        EXPECT_NEAR(out[0].color.r, grey_at(ray.at(enter).x) * a, 3e-3f);
        EXPECT_NEAR(out[1].color.r, grey_at(ray.at(leave).x) * a, 3e-3f);
      } else {  // the rod's near end, a cap facing the eye where it meets the ball, and so on
        ASSERT_EQ(out.size(), 4u) << y;
        EXPECT_LT(out[0].t, 20.5f / kAlongX.x);
        EXPECT_NEAR(out[1].t, enter, 0.02f) << y;
        EXPECT_EQ(out[1].front_facing, 0u);  // the kept side is in front of it
        EXPECT_NEAR(out[2].t, leave, 0.02f) << y;
        EXPECT_EQ(out[2].front_facing, 1u);
        EXPECT_GT(out[3].t, 39.5f / kAlongX.x);
      }
    }
  }
}

TEST(TubeClipMesh, PlanesAndMeshesKeepWhatAllOfThemKeep) {
  StreamlineObject o = test::rod(0.5, 0.5f);
  o.clip_planes.push_back({{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}});  // x >= 0
  o.clip_meshes.push_back({0, true});                           // inside x in [-4, 4]
  const auto meshes = objects_of({box({-4, -3, -3}, {4, 3, 3})});
  const auto out = fragments(o, meshes, Ray{{-30.0f, 0.1f, 0.1f}, kAlongX});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_NEAR(out[0].t, 30.0f / kAlongX.x, 1e-4f);  // the plane's cap
  EXPECT_NEAR(out[0].color.r, grey_at(0.0f) * tube_fragment_alpha(0.5f), 2e-3f);
  EXPECT_NEAR(out[1].t, 34.0f / kAlongX.x, 1e-4f);  // the box's
}

TEST(TubeClipMesh, ARayStartingInsideACutterIsInsideFromItsStart) {
  StreamlineObject o = test::rod(0.5, 0.5f);
  o.clip_meshes.push_back({0, false});
  const auto meshes = objects_of({box({-4, -3, -3}, {4, 3, 3})});
  // From x = 0, inside the box: nothing until the face x = 4, capped there, then the rod's end.
  const auto out = fragments(o, meshes, Ray{{0.0f, 0.1f, 0.1f}, kAlongX});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_NEAR(out[0].t, 4.0f / kAlongX.x, 1e-4f);
  EXPECT_EQ(out[0].front_facing, 1u);
  EXPECT_GT(out[1].t, 10.0f);
}

TEST(TubeClipMesh, TwoMeshesKeepWhereBothKeep) {
  StreamlineObject o = test::rod(0.5, 0.5f);
  o.clip_meshes.push_back({0, true});   // inside x in [-6, 6]
  o.clip_meshes.push_back({1, false});  // outside x in [-2, 1]
  const auto meshes = objects_of({box({-6, -3, -3}, {6, 3, 3}), box({-2, -3, -3}, {1, 3, 3})});
  const auto out = fragments(o, meshes, Ray{{-30.0f, 0.1f, 0.1f}, kAlongX});
  ASSERT_EQ(out.size(), 4u);  // caps at -6, -2, 1 and 6
  const float at[] = {24.0f, 28.0f, 31.0f, 36.0f};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(out[i].t, at[i] / kAlongX.x, 1e-4f) << i;
    EXPECT_EQ(out[i].front_facing, i % 2 == 0 ? 1u : 0u) << i;
  }
}

TEST(TubeClipMesh, AnIndexOutsideTheScenesMeshesIsAnError) {
  StreamlineObject o = test::rod(0.5, 1.0f);
  o.clip_meshes.push_back({2, true});
  const TubeGeometry tubes(o);
  const auto meshes = objects_of({box({-4, -3, -3}, {4, 3, 3})});
  EXPECT_THROW(make_tube_look(o, tubes, meshes), Error);
}

TEST(TubeClipMesh, AClipMeshOverTheMemoryBudgetIsRefusedByName) {
  StreamlineObject o = test::rod(0.5, 1.0f);
  o.clip_meshes.push_back({0, true});
  const auto meshes = objects_of({icosphere({0, 0, 0}, 3.0f, 4)});  // 5,120 triangles
  set_input_limits({100 * 1024, false});
  try {
    make_tube_clip_meshes(o, meshes);
    ADD_FAILURE() << "a clip mesh over the budget was built";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("clip meshes' 5120 triangles"), std::string::npos)
        << e.what();
  }
  set_input_limits({});
  EXPECT_NE(make_tube_clip_meshes(o, meshes), nullptr);
}

}  // namespace
}  // namespace imx
