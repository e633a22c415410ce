#include "volume/octant_distance.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace imx {
namespace {

// The definition: the Chebyshev distance to the nearest occupied cell in the octant.
std::vector<uint8_t> brute_force(const std::vector<uint8_t>& occ, glm::ivec3 d) {
  std::vector<uint8_t> out(kOctants * occ.size(), 255);
  for (int o = 0; o < kOctants; ++o) {
    const glm::ivec3 s((o & 1) ? -1 : 1, (o & 2) ? -1 : 1, (o & 4) ? -1 : 1);
    for (int z = 0; z < d.z; ++z)
      for (int y = 0; y < d.y; ++y)
        for (int x = 0; x < d.x; ++x) {
          int best = 255;
          for (int k = 0; k < d.z; ++k)
            for (int j = 0; j < d.y; ++j)
              for (int i = 0; i < d.x; ++i) {
                const glm::ivec3 ahead = (glm::ivec3(i, j, k) - glm::ivec3(x, y, z)) * s;
                if (occ[(k * d.y + j) * d.x + i] &&
                    glm::all(glm::greaterThanEqual(ahead, glm::ivec3(0))))
                  best = std::min(best, std::max({ahead.x, ahead.y, ahead.z}));
              }
          out[kOctants * ((z * d.y + y) * d.x + x) + o] = static_cast<uint8_t>(best);
        }
  }
  return out;
}

TEST(OctantDistance, EqualsBruteForceOnRandomGrids) {
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> size(1, 11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int trial = 0; trial < 100; ++trial) {
    glm::ivec3 d(size(rng), size(rng), size(rng));
    float density = trial % 4 == 0 ? 0.0f : 0.3f * u(rng) * u(rng);
    std::vector<uint8_t> occ(static_cast<size_t>(d.x) * d.y * d.z);
    for (auto& o : occ) o = u(rng) < density ? 1 : 0;
    if (trial % 8 == 1) std::fill(occ.begin(), occ.end(), 0), occ[occ.size() / 2] = 1;
    std::vector<uint8_t> out(kOctants * occ.size());
    octant_distance(occ, d, out);
    ASSERT_EQ(out, brute_force(occ, d)) << "grid " << d.x << "x" << d.y << "x" << d.z;
  }
}

// Ahead of the one occupied cell the distance counts up; behind it nothing lies ahead.
TEST(OctantDistance, CountsTowardTheOctantAndSaturatesAt255) {
  glm::ivec3 d(300, 1, 1);
  std::vector<uint8_t> occ(300, 0), out(kOctants * 300);
  occ[299] = 1;
  octant_distance(occ, d, out);
  EXPECT_EQ(out[kOctants * 299], 0);
  EXPECT_EQ(out[kOctants * 289], 10);       // rising x: the cell 10 ahead
  EXPECT_EQ(out[kOctants * 289 + 1], 255);  // falling x: nothing ahead
  EXPECT_EQ(out[kOctants * 45], 254);
  EXPECT_EQ(out[kOctants * 44], 255);
  EXPECT_EQ(out[kOctants * 289 + 6], 10);  // y and z do not move in a one-cell-thick grid
}

}  // namespace
}  // namespace imx
