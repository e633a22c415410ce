#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <random>
#include <vector>

#include "volume/chebyshev_distance.hpp"

namespace imx {
namespace {

std::vector<uint8_t> brute_force(const std::vector<uint8_t>& occ, glm::ivec3 d) {
  std::vector<uint8_t> out(occ.size(), 255);
  for (int z = 0; z < d.z; ++z)
    for (int y = 0; y < d.y; ++y)
      for (int x = 0; x < d.x; ++x) {
        int best = 255;
        for (int k = 0; k < d.z; ++k)
          for (int j = 0; j < d.y; ++j)
            for (int i = 0; i < d.x; ++i)
              if (occ[(k * d.y + j) * d.x + i])
                best =
                    std::min(best, std::max({std::abs(i - x), std::abs(j - y), std::abs(k - z)}));
        out[(z * d.y + y) * d.x + x] = static_cast<uint8_t>(best);
      }
  return out;
}

TEST(ChebyshevDistance, EqualsBruteForceOnRandomGrids) {
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> size(1, 13);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int trial = 0; trial < 120; ++trial) {
    glm::ivec3 d(size(rng), size(rng), size(rng));
    float density = trial % 4 == 0 ? 0.0f : 0.3f * u(rng) * u(rng);
    std::vector<uint8_t> occ(static_cast<size_t>(d.x) * d.y * d.z);
    for (auto& o : occ) o = u(rng) < density ? 1 : 0;
    if (trial % 8 == 1) std::fill(occ.begin(), occ.end(), 0), occ[occ.size() / 2] = 1;
    std::vector<uint8_t> out(occ.size());
    chebyshev_distance(occ, d, out);
    ASSERT_EQ(out, brute_force(occ, d)) << "grid " << d.x << "x" << d.y << "x" << d.z;
  }
}

TEST(ChebyshevDistance, SaturatesAt255) {
  glm::ivec3 d(300, 1, 1);
  std::vector<uint8_t> occ(300, 0), out(300);
  occ[0] = 1;
  chebyshev_distance(occ, d, out);
  EXPECT_EQ(out[10], 10);
  EXPECT_EQ(out[254], 254);
  EXPECT_EQ(out[255], 255);
  EXPECT_EQ(out[299], 255);
}

}  // namespace
}  // namespace imx
