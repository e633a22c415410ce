#include "dist/partition.hpp"

#include <gtest/gtest.h>

#include <set>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"
#include "intermix/scene.hpp"

namespace imx {
namespace {

// A scene outline: volumes of the given dims (one voxel held, as a distributed outline has),
// meshes of the given triangle counts.
Scene outline(const std::vector<glm::ivec3>& volumes, const std::vector<size_t>& meshes,
              const glm::dmat4& placement = glm::dmat4(1.0)) {
  Scene s;
  for (size_t v = 0; v < volumes.size(); ++v) {
    VolumeObject o;
    o.name = fmt::format("v{}", v);
    auto data = std::make_shared<VolumeData>();
    data->dims = glm::ivec3(1);
    data->voxels = VoxelBuffer<uint8_t>(std::vector<uint8_t>(1, 0));
    o.data = data;
    o.index_to_world = placement;
    o.source_dims = volumes[v];
    o.region = {glm::ivec3(0), glm::ivec3(1)};
    s.order.push_back({ObjectKind::volume, static_cast<int>(s.volumes.size())});
    s.volumes.push_back(o);
  }
  for (size_t m = 0; m < meshes.size(); ++m) {
    MeshObject o;
    o.name = fmt::format("m{}", m);
    auto mesh = std::make_shared<Mesh>();
    mesh->triangles.resize(meshes[m]);
    o.mesh = mesh;
    s.order.push_back({ObjectKind::mesh, static_cast<int>(s.meshes.size())});
    s.meshes.push_back(o);
  }
  return s;
}

TEST(Partition, BricksTileTheGridAndShareTheirCuts) {
  const glm::ivec3 dims(100, 80, 60);
  for (int ranks : {1, 2, 3, 4, 7, 8}) {
    Partition p = plan_partition(outline({dims}, {}), ranks, PartitionMode::bricks);
    ASSERT_EQ(p.mode, PartitionMode::bricks);
    // Every cell (unit cube between grid points) belongs to exactly one brick.
    std::vector<int> owners(static_cast<size_t>(99 * 79 * 59), 0);
    for (const RankPart& r : p.ranks) {
      ASSERT_EQ(r.bricks.size(), 1u) << ranks;
      const VolumeBrick& b = r.bricks.at("v0");
      for (int a = 0; a < 3; ++a) {
        // the apron: one voxel towards each neighbour, none at the volume's faces
        EXPECT_EQ(b.read.lo[a], b.lo[a] > 0 ? b.lo[a] - 1 : 0);
        EXPECT_EQ(b.read.hi[a], b.hi[a] < dims[a] - 1 ? b.hi[a] + 2 : dims[a]);
      }
      for (int z = b.lo.z; z < b.hi.z; ++z)
        for (int y = b.lo.y; y < b.hi.y; ++y)
          for (int x = b.lo.x; x < b.hi.x; ++x)
            ++owners[static_cast<size_t>((z * 79 + y) * 99 + x)];
    }
    for (int n : owners) ASSERT_EQ(n, 1) << ranks << " ranks";
  }
}

TEST(Partition, BrickBoundsKeepOnlyTheOwnSideOfEachCut) {
  // A sheared, scaled placement: the cut planes must follow index space, not world axes.
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(0.8, 0.1, 0.0, 0.0);
  m[1] = glm::dvec4(0.2, 1.1, 0.0, 0.0);
  m[2] = glm::dvec4(0.0, 0.3, 2.0, 0.0);
  m[3] = glm::dvec4(-40.0, 5.0, 7.0, 1.0);
  const glm::ivec3 dims(64, 64, 64);
  Partition p = plan_partition(outline({dims}, {}, m), 2, PartitionMode::bricks);
  const VolumeBrick& a = p.ranks[0].bricks.at("v0");
  const VolumeBrick& b = p.ranks[1].bricks.at("v0");
  ASSERT_EQ(a.bounds.size(), 1u);
  ASSERT_EQ(b.bounds.size(), 1u);
  // The same plane, facing each brick's own side.
  EXPECT_EQ(a.bounds[0].point, b.bounds[0].point);
  EXPECT_EQ(a.bounds[0].normal, -b.bounds[0].normal);
  auto kept = [&](const VolumeBrick& brick, glm::dvec3 index) {
    glm::dvec3 world(m * glm::dvec4(index, 1.0));
    return glm::dot(world - brick.bounds[0].point, brick.bounds[0].normal) >= 0.0;
  };
  glm::dvec3 inside_a((a.lo + a.hi) / 2), inside_b((b.lo + b.hi) / 2);
  EXPECT_TRUE(kept(a, inside_a));
  EXPECT_FALSE(kept(a, inside_b));
  EXPECT_TRUE(kept(b, inside_b));
  EXPECT_FALSE(kept(b, inside_a));
}

TEST(Partition, ObjectsAreDealtOnceLargestFirst) {
  Scene s = outline({{128, 128, 128}, {64, 64, 64}, {64, 64, 64}}, {20000, 100});
  Partition p = plan_partition(s, 2, PartitionMode::objects);
  std::multiset<size_t> dealt;
  for (const RankPart& r : p.ranks) {
    EXPECT_TRUE(r.bricks.empty());
    dealt.insert(r.objects.begin(), r.objects.end());
  }
  EXPECT_EQ(dealt, (std::multiset<size_t>{0, 1, 2, 3, 4}));
  // The 128^3 volume alone outweighs the rest: it has a rank to itself.
  EXPECT_EQ(p.ranks[0].objects, (std::vector<size_t>{0}));
}

TEST(Partition, PlanesGoWithTheVolumeTheySampleAndKeepItWhole) {
  Scene s = outline({{128, 128, 128}}, {});
  PlaneObject plane;
  plane.name = "axial";
  plane.volume = 0;
  s.order.push_back({ObjectKind::plane, 0});
  s.planes.push_back(plane);
  for (PartitionMode mode : {PartitionMode::objects, PartitionMode::bricks}) {
    Partition p = plan_partition(s, 3, mode);
    size_t with = 0;
    for (const RankPart& r : p.ranks) {
      EXPECT_TRUE(r.bricks.empty());
      if (!r.objects.empty()) {
        EXPECT_EQ(r.objects, (std::vector<size_t>{0, 1}));
        ++with;
      }
    }
    EXPECT_EQ(with, 1u);
  }
}

TEST(Partition, AutoBricksOneLargeVolumeAndDealsBalancedObjects) {
  EXPECT_EQ(plan_partition(outline({{256, 256, 256}}, {500}), 4, PartitionMode::automatic).mode,
            PartitionMode::bricks);
  EXPECT_EQ(
      plan_partition(outline({{64, 64, 64}, {64, 64, 64}}, {}), 2, PartitionMode::automatic).mode,
      PartitionMode::objects);
}

TEST(Partition, SmallVolumesAreNotBricked) {
  Partition p =
      plan_partition(outline({{256, 256, 256}, {16, 16, 16}}, {}), 4, PartitionMode::bricks);
  size_t bricks = 0, whole = 0;
  for (const RankPart& r : p.ranks) {
    bricks += r.bricks.size();
    whole += r.objects.size();
  }
  EXPECT_EQ(bricks, 4u);
  EXPECT_EQ(whole, 1u);
}

TEST(Partition, RefusesCsgAndUnknownModes) {
  Scene s = outline({{64, 64, 64}}, {});
  s.csg = CsgExpression{};
  try {
    plan_partition(s, 2, PartitionMode::objects);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("csg"), std::string::npos);
  }
  try {
    parse_partition_mode("slabs");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'slabs'"), std::string::npos);
  }
}

}  // namespace
}  // namespace imx
