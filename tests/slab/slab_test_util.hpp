// Helpers for the slab tests: seeded random slabs and sequences, tolerant comparisons.
#pragma once
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <glm/vec4.hpp>

#include "slab/slab.hpp"

namespace imx::test {

inline ::testing::AssertionResult near4(const glm::vec4& a, const glm::vec4& b, float tol) {
  for (int i = 0; i < 4; ++i)
    if (!(std::abs(a[i] - b[i]) <= tol))
      return ::testing::AssertionFailure()
             << "(" << a.r << ", " << a.g << ", " << a.b << ", " << a.a << ") vs (" << b.r << ", "
             << b.g << ", " << b.b << ", " << b.a << "), component " << i << " tol " << tol;
  return ::testing::AssertionSuccess();
}

inline ::testing::AssertionResult near_slab(const Slab& a, const Slab& b, float tol) {
  if (!(std::abs(a.t_back - b.t_back) <= tol) || !(std::abs(a.thickness - b.thickness) <= tol))
    return ::testing::AssertionFailure() << "interval [" << a.front() << ", " << a.t_back
                                         << "] vs [" << b.front() << ", " << b.t_back << "]";
  return near4(a.color, b.color, tol);
}

struct SlabRng {
  std::mt19937 gen;
  explicit SlabRng(unsigned seed) : gen(seed) {}

  float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(gen); }
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(gen); }
  bool chance(float p) { return uniform(0.0f, 1.0f) < p; }

  // Valid premultiplied visibility: rgb in [0, A]; sometimes exactly 0 or 1 opaque.
  glm::vec4 visibility() {
    float a = chance(0.1f) ? 1.0f : chance(0.05f) ? 0.0f : uniform(0.0f, 1.0f);
    return {uniform(0.0f, a), uniform(0.0f, a), uniform(0.0f, a), a};
  }

  // Depths on a 1/8 grid, so coincident boundaries, touching slabs and equal backs are common.
  float grid(float lo, float hi) { return std::round(uniform(lo, hi) * 8.0f) / 8.0f; }

  // n sorted slabs that do not overlap one another (touching and surfaces included).
  std::vector<Slab> disjoint_sequence(int n, float start = 0.0f) {
    std::vector<Slab> out;
    float at = start;
    bool last_surface = false;
    for (int i = 0; i < n; ++i) {
      bool surface = chance(0.2f);
      float gap = chance(0.3f) ? 0.0f : grid(0.125f, 2.0f);
      if (surface && last_surface && gap == 0.0f) gap = 0.125f;  // no two surfaces at one depth
      float front = at + gap;
      float back = surface ? front : front + grid(0.125f, 3.0f);
      out.push_back(Slab::between(front, back, visibility()));
      at = back;
      last_surface = surface;
    }
    return out;
  }
};

// Splits one sorted non-overlapping sequence at random into two (P and Q).
inline void deal(SlabRng& rng, const std::vector<Slab>& all, std::vector<Slab>& p,
                 std::vector<Slab>& q) {
  for (const Slab& s : all) (rng.chance(0.5f) ? p : q).push_back(s);
}

}  // namespace imx::test
