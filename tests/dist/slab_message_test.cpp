#include "dist/slab_message.hpp"

#include <gtest/gtest.h>

#include <random>

#include "intermix/error.hpp"

namespace imx {
namespace {

// Arrays of `samples` samples, every third one empty, the rest 1..capacity sorted disjoint slabs.
ZtBuffer random_arrays(size_t samples, int capacity, SlabFormat format, uint32_t seed) {
  ZtBuffer b(samples, capacity, format);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (size_t i = 0; i < samples; ++i) {
    if (i % 3 == 0) continue;
    int n = 1 + static_cast<int>(rng() % static_cast<uint32_t>(capacity));
    std::vector<Slab> slabs;
    float t = 10.0f + u(rng);
    for (int k = 0; k < n; ++k) {
      float d = 0.5f + u(rng);
      t += d + u(rng);
      float a = 0.05f + 0.5f * u(rng);
      slabs.push_back({t, d, glm::vec4(u(rng) * a, u(rng) * a, u(rng) * a, a)});
    }
    b.store(i, slabs);
  }
  return b;
}

TEST(SlabMessage, EmptySamplesCostABitAndSlabsTheirStoredSize) {
  for (SlabFormat f : {SlabFormat::rgba8, SlabFormat::rgba32f}) {
    ZtBuffer b = random_arrays(64, 4, f, 1);
    size_t slabs = 0, nonempty = 0;
    for (size_t i = 16; i < 48; ++i) {
      slabs += static_cast<size_t>(b.count(i));
      nonempty += b.count(i) > 0;
    }
    std::vector<std::byte> m = encode_slab_message(b, {8, 24}, 2);  // samples 16..47
    EXPECT_EQ(m.size(), 32 / 8 + nonempty + slabs * static_cast<size_t>(slab_bytes(f)));
  }
  ZtBuffer empty(100, 8, SlabFormat::rgba32f);
  EXPECT_EQ(encode_slab_message(empty, {0, 100}, 1).size(), 13u);
}

TEST(SlabMessage, ThreadsEncodeTheSameBytes) {
  // 3 * 4096 + 13 samples: blocks of 4096, the last one short and not a multiple of 8.
  ZtBuffer b = random_arrays(3 * 4096 + 40, 5, SlabFormat::rgba32f, 9);
  std::vector<std::byte> one = encode_slab_message(b, {3, 3 * 4096 + 16}, 1, 1);
  EXPECT_EQ(encode_slab_message(b, {3, 3 * 4096 + 16}, 1, 4), one);
}

TEST(SlabMessage, FullArraysReachTheAnnouncedBound) {
  for (SlabFormat f : {SlabFormat::rgba8, SlabFormat::rgba32f}) {
    ZtBuffer full(40, 3, f);
    const std::vector<Slab> three{{11.0f, 1.0f, glm::vec4(0.1f)},
                                  {13.0f, 1.0f, glm::vec4(0.2f)},
                                  {15.0f, 1.0f, glm::vec4(0.3f)}};
    for (size_t i = 0; i < 40; ++i) full.store(i, three);
    EXPECT_EQ(encode_slab_message(full, {2, 18}, 2).size(),
              max_slab_message_bytes(full, {2, 18}, 2));
    ZtBuffer sparse = random_arrays(40, 3, f, 5);
    EXPECT_LT(encode_slab_message(sparse, {2, 18}, 2).size(),
              max_slab_message_bytes(sparse, {2, 18}, 2));
  }
}

TEST(SlabMessage, MergingIntoEmptyArraysGivesTheSentOnes) {
  for (SlabFormat f : {SlabFormat::rgba8, SlabFormat::rgba32f}) {
    ZtBuffer sent = random_arrays(300, 6, f, 2);
    std::vector<std::byte> m = encode_slab_message(sent, {50, 250}, 1);
    ZtBuffer got(300, 6, f);
    merge_slab_message(got, {50, 250}, 1, m, false, IntermixSettings{}, 2);
    Slab a[16], b[16];
    for (size_t i = 0; i < 300; ++i) {
      int n = got.load(i, b);
      if (i < 50 || i >= 250) {
        EXPECT_EQ(n, 0);
        continue;
      }
      ASSERT_EQ(n, sent.load(i, a)) << i;
      for (int k = 0; k < n; ++k) {
        EXPECT_FLOAT_EQ(b[k].t_back, a[k].t_back);
        EXPECT_FLOAT_EQ(b[k].thickness, a[k].thickness);
        EXPECT_NEAR(b[k].color.a, a[k].color.a, 1e-6f);
      }
    }
  }
}

TEST(SlabMessage, MergeEqualsTheKernelOnBothArrays) {
  ZtBuffer mine = random_arrays(200, 8, SlabFormat::rgba32f, 3);
  ZtBuffer theirs = random_arrays(200, 8, SlabFormat::rgba32f, 4);
  ZtBuffer expected = mine;
  IntermixSettings mix;
  Slab a[16], b[16], out[16];
  for (size_t i = 0; i < 200; ++i) {
    int na = expected.load(i, a), nb = theirs.load(i, b);
    if (nb == 0) continue;
    SlabList list(std::span<Slab>(out, 8));
    intermix(std::span<const Slab>(b, nb), std::span<const Slab>(a, na), list, mix);
    expected.store(i, list.items());
  }
  merge_slab_message(mine, {0, 200}, 1, encode_slab_message(theirs, {0, 200}, 1), false, mix, 2);
  for (size_t i = 0; i < 200; ++i) {
    int n = mine.load(i, a);
    ASSERT_EQ(n, expected.load(i, b));
    for (int k = 0; k < n; ++k) EXPECT_EQ(a[k].color, b[k].color) << i;
  }
}

TEST(SlabMessage, RefusesMalformedMessagesBeforeChangingAnything) {
  ZtBuffer sent = random_arrays(40, 4, SlabFormat::rgba8, 5);
  std::vector<std::byte> good = encode_slab_message(sent, {0, 40}, 1);
  ZtBuffer target(40, 4, SlabFormat::rgba8);
  auto refused = [&](std::vector<std::byte> m) {
    try {
      merge_slab_message(target, {0, 40}, 1, m, true, IntermixSettings{}, 1);
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("slab message"), std::string::npos);
      for (size_t i = 0; i < 40; ++i) EXPECT_EQ(target.count(i), 0);
      return true;
    }
    return false;
  };
  std::vector<std::byte> truncated(good.begin(), good.end() - 1);
  EXPECT_TRUE(refused(truncated));
  std::vector<std::byte> longer = good;
  longer.push_back(std::byte{0});
  EXPECT_TRUE(refused(longer));
  std::vector<std::byte> too_many = good;
  too_many[5] = std::byte{9};  // the first count byte (mask: 5 bytes): over the capacity of 4
  EXPECT_TRUE(refused(too_many));
  EXPECT_TRUE(refused({}));
  EXPECT_FALSE(refused(good));
}

}  // namespace
}  // namespace imx
