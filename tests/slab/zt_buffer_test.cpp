// ZT-buffer storage: both packed slab formats stored and loaded, on hand-made slabs.
#include "slab/zt_buffer.hpp"

#include <gtest/gtest.h>

#include <span>

namespace imx {
namespace {

TEST(ZslabBuffer, PacksBothFormats) {
  Slab s[3] = {{1.0f, 0.5f, glm::vec4(0.1f, 0.2f, 0.3f, 0.4f)},
               {3.0f, 0.0f, glm::vec4(0.0f)},
               {7.0f, 2.0f, glm::vec4(0.001f, 0.0f, 0.002f, 0.004f)}};
  for (SlabFormat f : {SlabFormat::rgba32f, SlabFormat::rgba8}) {
    ZtBuffer b(2, 4, f);
    b.store(1, s);
    Slab back[4];
    ASSERT_EQ(b.load(0, back), 0);
    ASSERT_EQ(b.load(1, back), 3);
    float tol = f == SlabFormat::rgba8 ? 0.5f / 255.0f * 1.01f : 0.0f;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(back[k].t_back, s[k].t_back);
      EXPECT_EQ(back[k].thickness, s[k].thickness);
      EXPECT_NEAR(back[k].color.a, s[k].color.a, tol);
      // straight colour in 8 bits: premultiplied error scales with opacity
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(back[k].color[i], s[k].color[i], tol);
    }
    EXPECT_EQ(b.bytes(), 2u * 4u * static_cast<size_t>(slab_bytes(f)));
    b.store(1, std::span<const Slab>(s, 1));
    EXPECT_EQ(b.load(1, back), 1);
  }
}

}  // namespace
}  // namespace imx
