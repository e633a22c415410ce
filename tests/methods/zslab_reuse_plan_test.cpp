// The reuse plan of a cached zSlab frame (zslab_reuse_plan.hpp): eviction within the budget,
// kept arrays matched by key and shape, the merged prefix read, written or dropped.
#include "methods/zslab/zslab_reuse_plan.hpp"

#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "methods/zslab/zslab_kept.hpp"

namespace imx {
namespace {

constexpr size_t kSamples = 100;
constexpr int kLayers = 8;

// Four deferred stages with own arrays of 4, 8, 2 and 4 slots and a roomy budget, nothing kept.
ZslabReuseInput four_stages() {
  ZslabReuseInput in;
  in.own_key = {11, 12, 13, 14};
  in.capacity = {4, 8, 2, 4};
  in.chain = {100, 101, 102, 103, 104};
  in.samples = kSamples;
  in.layers = kLayers;
  in.budget = uint64_t{1} << 30;
  return in;
}

// `in` as the cache holds it after a frame that kept every own array.
void keep_all(ZslabReuseInput& in) {
  in.kept_own.clear();
  for (size_t k = 0; k < in.own_key.size(); ++k)
    in.kept_own.push_back(KeptArrayShape{in.own_key[k], kSamples, in.capacity[k]});
}

uint64_t bytes(int capacity) {
  return KeptSlabArrays::bytes_for(kSamples, capacity);
}

TEST(ZslabReusePlan, FirstFrameRendersEveryStageAndKeepsNoPrefix) {
  const ZslabReusePlan p = plan_zslab_reuse(four_stages());
  EXPECT_EQ(p.keep, (std::vector<bool>{true, true, true, true}));
  EXPECT_EQ(p.matched, (std::vector<int>{-1, -1, -1, -1}));
  EXPECT_EQ(p.render, (std::vector<bool>{true, true, true, true}));
  EXPECT_EQ(p.first, 0u);
  EXPECT_EQ(p.start, 0u);
  EXPECT_FALSE(p.read_prefix);
  EXPECT_FALSE(p.write_prefix);  // nothing before the first rendered stage
  EXPECT_EQ(p.own_bytes, bytes(4) + bytes(8) + bytes(2) + bytes(4));
  EXPECT_EQ(p.kept_bytes(), p.own_bytes);
  EXPECT_EQ(p.stages_run(), 4);
  EXPECT_EQ(p.stages_merged(), 4);
}

TEST(ZslabReusePlan, BudgetEvictsTheLargestFirstThenTheLaterStage) {
  ZslabReuseInput in = four_stages();
  in.budget = bytes(4) + bytes(2);  // room for stage 0 (or 3) and stage 2
  ZslabReusePlan p = plan_zslab_reuse(in);
  EXPECT_EQ(p.keep, (std::vector<bool>{true, false, true, false}));
  EXPECT_EQ(p.own_bytes, bytes(4) + bytes(2));
  in.budget = 0;  // keeps nothing, and an unsplit stage (capacity 0) never
  in.capacity[2] = 0;
  p = plan_zslab_reuse(in);
  EXPECT_EQ(p.keep, (std::vector<bool>{false, false, false, false}));
  EXPECT_EQ(p.own_bytes, 0u);
  EXPECT_FALSE(p.write_prefix);
}

TEST(ZslabReusePlan, UnchangedFrameMergesKeptArraysAndWritesThePrefixOfAll) {
  ZslabReuseInput in = four_stages();
  keep_all(in);
  std::swap(in.kept_own[0], in.kept_own[3]);  // the cache's order is not the stages'
  const ZslabReusePlan p = plan_zslab_reuse(in);
  EXPECT_EQ(p.matched, (std::vector<int>{3, 1, 2, 0}));
  EXPECT_EQ(p.render, (std::vector<bool>{false, false, false, false}));
  EXPECT_EQ(p.first, 4u);
  EXPECT_TRUE(p.write_prefix);
  EXPECT_EQ(p.kept_bytes(), p.own_bytes + bytes(kLayers));
  EXPECT_EQ(p.stages_run(), 0);
}

TEST(ZslabReusePlan, AnEditRendersItsStageAndMergesFromTheKeptPrefix) {
  ZslabReuseInput in = four_stages();
  keep_all(in);
  in.kept_own[2]->key = 99;  // stage 2's object changed
  in.prefix = KeptArrayShape{in.chain[2], kSamples, kLayers};
  in.prefix_stage = 2;
  const ZslabReusePlan p = plan_zslab_reuse(in);
  EXPECT_EQ(p.matched, (std::vector<int>{0, 1, -1, 3}));
  EXPECT_EQ(p.first, 2u);
  EXPECT_TRUE(p.read_prefix);
  EXPECT_EQ(p.start, 2u);
  EXPECT_EQ(p.render, (std::vector<bool>{false, false, true, false}));
  EXPECT_FALSE(p.write_prefix);  // it is already the prefix before stage 2
  EXPECT_FALSE(p.drop_prefix);
  EXPECT_EQ(p.stages_run(), 1);
  EXPECT_EQ(p.stages_merged(), 2);

  // The same edit with the prefix of another chain, or of another shape: merged from stage 0,
  // and the merged array before stage 2 written as the new prefix.
  for (int variant = 0; variant < 2; ++variant) {
    ZslabReuseInput other = in;
    if (variant == 0) other.prefix->key = 7;
    if (variant == 1) other.prefix->capacity = kLayers - 1;
    const ZslabReusePlan q = plan_zslab_reuse(other);
    EXPECT_FALSE(q.read_prefix);
    EXPECT_TRUE(q.drop_prefix);
    EXPECT_EQ(q.start, 0u);
    EXPECT_TRUE(q.write_prefix);
    EXPECT_EQ(q.stages_merged(), 4);
  }
}

TEST(ZslabReusePlan, APrefixBeyondTheFirstChangedStageIsNotRead) {
  ZslabReuseInput in = four_stages();
  keep_all(in);
  in.kept_own[1].reset();  // dropped: stage 1 is rendered
  in.prefix = KeptArrayShape{in.chain[3], kSamples, kLayers};
  in.prefix_stage = 3;
  const ZslabReusePlan p = plan_zslab_reuse(in);
  EXPECT_EQ(p.first, 1u);
  EXPECT_FALSE(p.read_prefix);
  EXPECT_EQ(p.start, 0u);
  EXPECT_FALSE(p.write_prefix);  // one merge before stage 1 is not worth an array
  EXPECT_TRUE(p.drop_prefix);
}

TEST(ZslabReusePlan, AKeptPrefixOverTheBudgetIsReadThenDropped) {
  ZslabReuseInput in = four_stages();
  keep_all(in);
  in.kept_own[3]->key = 99;
  in.prefix = KeptArrayShape{in.chain[2], kSamples, kLayers};
  in.prefix_stage = 2;
  in.budget = bytes(4) + bytes(8) + bytes(2) + bytes(4);  // the own arrays, no prefix
  const ZslabReusePlan p = plan_zslab_reuse(in);
  EXPECT_TRUE(p.read_prefix);
  EXPECT_EQ(p.start, 2u);
  EXPECT_FALSE(p.write_prefix);
  EXPECT_TRUE(p.drop_prefix);
  EXPECT_EQ(p.kept_bytes(), in.budget + bytes(kLayers));  // still held during the frame
}

TEST(ZslabReusePlan, EachKeptArrayServesOneStage) {
  ZslabReuseInput in = four_stages();
  in.own_key = {5, 5, 6, 6};  // two stages with the same key and shape
  in.capacity = {4, 4, 4, 4};
  in.kept_own = {KeptArrayShape{5, kSamples, 4}, std::nullopt, KeptArrayShape{6, kSamples, 4},
                 KeptArrayShape{6, kSamples + 1, 4}};
  const ZslabReusePlan p = plan_zslab_reuse(in);
  EXPECT_EQ(p.matched, (std::vector<int>{0, -1, 2, -1}));
  EXPECT_EQ(p.first, 1u);
}

}  // namespace
}  // namespace imx
