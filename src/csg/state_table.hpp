// CsgTable: the clipping states of a normalized expression, simplified, and the per-ray tests.
#pragma once
#include <cmath>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "csg/clip_state.hpp"
#include "csg/normalize.hpp"

namespace imx {

enum class CsgSimplify { none, merge, full };

// "none" | "merge" | "full" (render.csg_simplify); throws Error otherwise.
CsgSimplify parse_csg_simplify(std::string_view text);

// World AABB of a primitive; empty when lo > hi on some axis. Touching boxes meet.
struct CsgBox {
  glm::dvec3 lo{INFINITY}, hi{-INFINITY};
};

// The clipping states of an expression and what the per-ray tests need.
struct CsgTable {
  int primitive_count = 0;
  PrimitiveMask used = 0;       // the expression's primitives: bits 0..primitive_count-1
  PrimitiveMask geometric = 0;  // primitives with region presence
  std::vector<ClipState> states;
};

// What each stage did, for `intermix-lab csg`; stages past the requested level stay empty.
struct CsgTableReport {
  std::vector<ClipState> products;       // as normalized, without x ∧ ¬x
  std::vector<ClipState> after_merge;    // duplicates, absorption, X1Y + X0Y = X2Y
  std::vector<ClipState> after_pruning;  // bounding-box rules, then merged again
  std::vector<ClipState> after_full;     // widened to primes, minus redundant ones
  std::vector<std::string> pruned;       // one line per thing the boxes removed
};

// The state table of `products` at simplification `level`:
//   none:  the products as they are;
//   merge: sorted, without duplicates, absorbed (12 + 11 -> 12), X1Y + X0Y -> X2Y to a fixed
//          point; with `boxes` (boxes[k] for primitive k) also pruned: a state whose 1-digit boxes
//          do not meet is dropped, and a 0-digit whose box misses theirs becomes 2;
//   full:  merge, then the prime implicants (Tison's consensus) with "nothing present" as a
//          don't care; each merged state becomes the largest prime containing it (so the table
//          never grows), and redundant states go (checked on the truth table when
//          primitive_count <= 20): 12 + 21 -> 22. The table may match `present` = 0, which
//          renders nothing anyway.
// Pruned tables equal the expression only where the boxes allow the presence pattern. Throws Error
// naming the count when a stage holds more than max_states states. An empty result is returned as
// an empty table; the caller decides what an empty expression means.
CsgTable build_table(std::span<const CsgProduct> products, int primitive_count,
                     PrimitiveMask geometric, CsgSimplify level, std::span<const CsgBox> boxes,
                     int max_states, CsgTableReport* report = nullptr);

}  // namespace imx
