// The clip step of one ray (SPEC §7 clip geometry): which pieces of a ray each clipped volume
// keeps, from the clip meshes' sorted fragments; and what RayVolumes makes of them.
#include "frame/clip_intervals.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "homogeneous_volume.hpp"
#include "methods/mdvr/mdvr_kernel.hpp"
#include "volume/ray_volumes.hpp"

namespace imx {
namespace {

// Scene::order of the tests: 0 a volume, 1 mesh A, 2 mesh B, 3 a mesh that clips nothing.
const std::vector<int8_t> kSlots = {-1, 0, 1, -1};
constexpr PrimitiveMask kA = 1, kB = 2;

Fragment front(float t, uint32_t object) {
  return Fragment{t, glm::vec4(0.0f), object, 1};
}
Fragment back(float t, uint32_t object) {
  return Fragment{t, glm::vec4(0.0f), object, 0};
}

// The pieces volume 0 keeps under `rule` along `row`, as [t0, t1] pairs.
std::vector<RayInterval> kept(std::vector<Fragment> row, ClipState rule) {
  const std::vector<ClipState> rules = {rule};
  ClipPieces pieces;
  clip_volume(row, ClipView{kSlots, rules}, 0, pieces);
  return {pieces.piece, pieces.piece + pieces.count};
}

// "[0, 10) [20, inf)"
std::string text(const std::vector<RayInterval>& pieces) {
  std::string out;
  for (const RayInterval& p : pieces)
    out += fmt::format("{}[{}, {})", out.empty() ? "" : " ", p.t0, p.t1);
  return out;
}
std::string text(const RayInterval& p) {
  return text(std::vector<RayInterval>{p});
}

TEST(ClipIntervals, CuttingKeepsTheOutsideProbingTheInside) {
  const std::vector<Fragment> ball = {front(10, 1), back(20, 1)};
  EXPECT_EQ(text(kept(ball, {0, kA})), "[0, 10) [20, inf)");
  EXPECT_EQ(text(kept(ball, {kA, 0})), "[10, 20)");
  // A ray that misses the mesh: all of it is outside.
  EXPECT_EQ(text(kept({}, {0, kA})), "[0, inf)");
  EXPECT_TRUE(kept({}, {kA, 0}).empty());
}

TEST(ClipIntervals, AnEyeInsideTheCutterStartsInside) {
  // The near plane clipped the entry away: only the exit is left on the ray.
  const std::vector<Fragment> row = {back(5, 1)};
  EXPECT_EQ(text(kept(row, {0, kA})), "[5, inf)");
  EXPECT_EQ(text(kept(row, {kA, 0})), "[0, 5)");
  // Inside a concave cutter that the ray leaves, re-enters and leaves again.
  const std::vector<Fragment> twice = {back(5, 1), front(8, 1), back(12, 1)};
  EXPECT_EQ(text(kept(twice, {0, kA})), "[5, 8) [12, inf)");
}

TEST(ClipIntervals, TwoCuttersIntersectTheirKeptSets) {
  const std::vector<Fragment> row = {front(10, 1), front(15, 2), back(20, 1), back(30, 2)};
  EXPECT_EQ(text(kept(row, {0, kA | kB})), "[0, 10) [30, inf)");
  EXPECT_EQ(text(kept(row, {kA, kB})), "[10, 15)");
  EXPECT_EQ(text(kept(row, {kA | kB, 0})), "[15, 20)");
  EXPECT_EQ(text(kept(row, {kB, kA})), "[20, 30)");
}

TEST(ClipIntervals, OverlappingAndTouchingMeshesLeaveNoSliver) {
  // B nested in A: cutting both is cutting A.
  EXPECT_EQ(text(kept({front(10, 1), front(12, 2), back(18, 2), back(20, 1)}, {0, kA | kB})),
            "[0, 10) [20, inf)");
  // A's back face and B's front face at one depth: one cut from 10 to 30.
  EXPECT_EQ(text(kept({front(10, 1), back(20, 1), front(20, 2), back(30, 2)}, {0, kA | kB})),
            "[0, 10) [30, inf)");
  // One mesh overlapping itself (winding 2) is inside until both layers end.
  EXPECT_EQ(text(kept({front(10, 1), front(12, 1), back(18, 1), back(20, 1)}, {kA, 0})),
            "[10, 20)");
}

TEST(ClipIntervals, OtherObjectsFragmentsChangeNothing) {
  EXPECT_EQ(
      text(kept({front(3, 3), front(10, 1), back(14, 3), back(20, 1), front(25, 0)}, {0, kA})),
      "[0, 10) [20, inf)");
}

TEST(ClipIntervals, PiecesPastTheCapacityMergeIntoTheLast) {
  std::vector<Fragment> comb;
  for (int k = 0; k < 12; ++k) {
    comb.push_back(front(10.0f * (k + 1), 1));
    comb.push_back(back(10.0f * (k + 1) + 5.0f, 1));
  }
  const std::vector<RayInterval> p = kept(comb, {0, kA});
  ASSERT_EQ(p.size(), static_cast<size_t>(kMaxClipPieces));
  EXPECT_EQ(text(p.front()), "[0, 10)");
  EXPECT_EQ(text(p[kMaxClipPieces - 2]), "[65, 70)");
  // The rest, [75, 80) [85, 90) ... [125, inf), becomes one piece: sampled, not lost.
  EXPECT_EQ(text(p.back()), "[75, inf)");
}

TEST(ClipIntervals, ClipRayFillsEveryClippedVolume) {
  const std::vector<ClipState> rules = {{0, kA}, {}, {kA, 0}};
  RayClip clip;
  clip_ray(std::vector<Fragment>{front(10, 1), back(20, 1)}, ClipView{kSlots, rules}, clip);
  EXPECT_EQ(clip.clipped, 0b101u);
  EXPECT_EQ(clip.volume[0].count, 2);
  ASSERT_EQ(clip.volume[2].count, 1);
  EXPECT_EQ(text(clip.volume[2].piece[0]), "[10, 20)");
}

// RayVolumes reads each clipped volume's span through its pieces: clamped, the pieces outside
// left out, and a volume with nothing kept on the ray not marched.
TEST(ClipIntervals, RayVolumesKeepThePiecesWithinEachSpan) {
  const VolumeObject fog = test::homogeneous_volume(0.05f, glm::vec3(1.0f));
  const std::vector<PreparedVolume> vols = {PreparedVolume(fog), PreparedVolume(fog)};
  const Ray ray{{0.0f, 0.0f, -30.0f}, {0.0f, 0.0f, 1.0f}};  // the box is [20, 40]
  RayClip clip;
  clip.clipped = 0b11;
  clip.volume[0].add(0.0f, 5.0f);  // before the box
  clip.volume[0].add(15.0f, 25.0f);
  clip.volume[0].add(30.0f, INFINITY);
  clip.volume[1].add(0.0f, 19.0f);  // nothing of volume 1's box is kept
  const RayVolumes rv(ray, vols, 1.0, 4, {}, VolumeFilter(kEveryVolume, &clip));
  ASSERT_TRUE(rv.marched[0]);
  EXPECT_FALSE(rv.marched[1]);
  const KeptSpan k = rv.kept(0);
  ASSERT_EQ(k.size(), 2);
  EXPECT_EQ(text(k[0]), "[20, 25)");
  EXPECT_EQ(text(k[1]), "[30, 40)");
  EXPECT_TRUE(k.contains(22.0) && !k.contains(27.0) && k.contains(39.0) && !k.contains(40.0));

  // The mdvr kernel sees 15 mm of fog instead of 20: exactly the transmittance of 15 mm.
  MdvrParams p;
  p.step = 1.0f;
  const glm::vec4 one =
      trace_mdvr(ray, {}, std::span(vols).first(1), {}, p, VolumeFilter(kEveryVolume, &clip));
  EXPECT_NEAR(1.0f - one.a, std::pow(1.0f - 0.05f, 15.0f), 1e-4f);
}

}  // namespace
}  // namespace imx
