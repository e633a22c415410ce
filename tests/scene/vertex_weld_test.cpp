// The parallel weld against a map of first occurrences: the same ids, the same order, at any
// thread count.
#include "io/mesh/vertex_weld.hpp"

#include <array>
#include <bit>
#include <map>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "mesh_random.hpp"

namespace imx {
namespace {

detail::Weld reference_weld(const Mesh& m, bool by_color) {
  std::map<std::array<uint32_t, 6>, uint32_t> ids;
  detail::Weld out;
  for (size_t i = 0; i < m.positions.size(); ++i) {
    std::array<uint32_t, 6> key{};
    for (int c = 0; c < 3; ++c) {
      key[c] = std::bit_cast<uint32_t>(m.positions[i][c] == 0.0f ? 0.0f : m.positions[i][c]);
      if (by_color) key[3 + c] = std::bit_cast<uint32_t>(m.colors[i][c]);
    }
    auto [it, fresh] = ids.emplace(key, static_cast<uint32_t>(out.first.size()));
    if (fresh) out.first.push_back(static_cast<uint32_t>(i));
    out.id.push_back(it->second);
  }
  return out;
}

TEST(VertexWeld, MatchesFirstOccurrenceOrderWithAndWithoutColours) {
  for (bool colors : {false, true}) {
    const Mesh m = test::random_mesh(7, 5000, 60000, 10, colors);
    const detail::Weld expected = reference_weld(m, colors);
    const detail::Weld got = detail::weld_vertices(m.positions, m.colors);
    EXPECT_EQ(got.id, expected.id) << "colours " << colors;
    EXPECT_EQ(got.first, expected.first) << "colours " << colors;
    EXPECT_LT(got.first.size(), m.positions.size());  // the test does weld something
  }
}

TEST(VertexWeld, NegativeZeroWeldsAndTheThreadCountChangesNothing) {
  Mesh m;
  m.positions = {{0.0f, 1.0f, 2.0f}, {-0.0f, 1.0f, 2.0f}, {1.0f, 1.0f, 2.0f}, {0.0f, 1.0f, 2.0f}};
  const detail::Weld w = detail::weld_vertices(m.positions);
  EXPECT_EQ(w.id, (std::vector<uint32_t>{0, 0, 1, 0}));
  EXPECT_EQ(w.first, (std::vector<uint32_t>{0, 2}));

  const Mesh big = test::random_mesh(11, 20000, 200000, 10, true);
  const detail::Weld all = detail::weld_vertices(big.positions, big.colors);
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const detail::Weld single = detail::weld_vertices(big.positions, big.colors);
  EXPECT_EQ(all.id, single.id);
  EXPECT_EQ(all.first, single.first);
}

}  // namespace
}  // namespace imx
