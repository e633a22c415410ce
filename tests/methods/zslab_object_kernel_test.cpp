// The object-level split of a surface stage: peeling into the object's own slabs and merging
// them later gives run_surface_stage's bytes, also when the peeled layers need several RT passes.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "methods/zslab/zslab_object_kernel.hpp"

namespace imx {
namespace {

bool same_slabs(std::span<const Slab> a, std::span<const Slab> b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(&a[i], &b[i], sizeof(Slab)) != 0) return false;
  return true;
}

TEST(ZslabObjectKernel, PeelThenMergeEqualsTheWholeStage) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float thickness[3] = {0.8f, -1.0f, 2.5f};  // fixed, pixel footprint, fixed
  StageThickness th{thickness, 0.01f, 0.002f};
  int multi_pass = 0, differs_from_stored = 0;
  for (int trial = 0; trial < 400; ++trial) {
    ZslabParams p;
    p.layers = 2 + trial % 7;
    p.rt_layers = 1 + trial % 4;
    p.peel_layers = 1 + trial % 5;
    p.mix.overflow = trial % 2 ? Overflow::greedy : Overflow::tail;
    p.mix.a_ert = trial % 3 ? 0.99f : 1.0f;
    // the stored array: disjoint slabs sorted by back depth
    std::vector<Slab> stored;
    float t = 10.0f * u(rng);
    const int count = static_cast<int>(u(rng) * static_cast<float>(p.layers));
    for (int k = 0; k < count; ++k) {
      float d = 0.5f + 3.0f * u(rng);
      t += d + 2.0f * u(rng);
      float a = 0.6f * u(rng);
      stored.push_back({t, d, glm::vec4(a * u(rng), a * u(rng), a * u(rng), a)});
    }
    // fragments of three objects sorted by depth, some on one depth (coplanar)
    std::vector<Fragment> fragments;
    float z = 5.0f + 20.0f * u(rng);
    for (int k = 0; k < 1 + trial % 11; ++k) {
      if (u(rng) > 0.2f) z += 4.0f * u(rng);
      float a = u(rng);
      fragments.push_back({z, glm::vec4(a * u(rng), a * u(rng), a * u(rng), a),
                           static_cast<uint32_t>(trial + k) % 3, 1});
    }
    Slab whole_slots[kMaxZslabLayers], split_slots[kMaxZslabLayers], own[kMaxOwnSurfaceSlabs];
    SlabList whole(std::span<Slab>(whole_slots, static_cast<size_t>(p.layers)));
    SlabList split(std::span<Slab>(split_slots, static_cast<size_t>(p.layers)));
    const bool ran = run_surface_stage(fragments, th, stored, whole, p);
    const int m = peel_surface_slabs(fragments, th, p.peel_layers, own);
    ASSERT_LE(m, 3 * p.peel_layers);
    const bool merged =
        merge_surface_slabs(std::span<const Slab>(own, static_cast<size_t>(m)), stored, split, p);
    ASSERT_EQ(ran, merged);
    ASSERT_TRUE(same_slabs(whole.items(), split.items())) << "trial " << trial;
    multi_pass += m > p.rt_layers;
    differs_from_stored += !same_slabs(whole.items(), stored);
  }
  EXPECT_GT(multi_pass, 50);  // the peeled layers took more than one RT pass
  EXPECT_GT(differs_from_stored, 300);
}

TEST(ZslabObjectKernel, NoFragmentsLeaveTheStoredArray) {
  ZslabParams p;
  const float thickness[1] = {1.0f};
  StageThickness th{thickness, 0.0f, 0.0f};
  Slab own[4];
  EXPECT_EQ(peel_surface_slabs({}, th, p.peel_layers, own), 0);
  Slab slots[kMaxZslabLayers];
  slots[0] = {3.0f, 1.0f, glm::vec4(0.5f)};
  SlabList out(std::span<Slab>(slots, static_cast<size_t>(p.layers)), 1);
  EXPECT_FALSE(merge_surface_slabs({}, {}, out, p));
  EXPECT_EQ(out.size(), 1);
}

// Peeling keeps each object's first L fragments and never writes past the own array.
TEST(ZslabObjectKernel, PeelKeepsTheFirstLOfEachObject) {
  const float thickness[2] = {1.0f, 1.0f};
  StageThickness th{thickness, 0.0f, 0.0f};
  std::vector<Fragment> f;
  for (int k = 0; k < 6; ++k)
    f.push_back({static_cast<float>(k), glm::vec4(0.1f), static_cast<uint32_t>(k % 2), 1});
  Slab own[8];
  ASSERT_EQ(peel_surface_slabs(f, th, 2, own), 4);
  EXPECT_EQ(own[3].t_back, 3.0f);  // objects 0 and 1 alternate: depths 0, 1, 2, 3
  Slab two[2];
  EXPECT_EQ(peel_surface_slabs(f, th, 2, two), 2);
}

}  // namespace
}  // namespace imx
