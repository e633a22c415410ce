// Goldfeather normalization of a CsgExpr into a sum of products (SPEC §8's nine rules).
#pragma once
#include <cstdint>
#include <vector>

#include "csg/clip_state.hpp"
#include "csg/csg_expr.hpp"

namespace imx {

// One product: the intersection of the `pos` primitives minus those in `neg`.
struct CsgProduct {
  PrimitiveMask pos = 0, neg = 0;
  friend bool operator==(const CsgProduct&, const CsgProduct&) = default;
};

struct NormalizeLimits {
  int max_products = 4096;  // render.csg_max_states
  // Rewrite steps: one per rule application and one per node a rule copies, so the budget bounds
  // both time and memory.
  long max_rewrites = 1'000'000;
};

// The exact number of products normalization yields (before x ∧ ¬x ones are dropped), from the
// tree's shape alone; saturates at UINT64_MAX. Lets normalize() fail before any exponential work.
uint64_t count_products(const CsgExpr& e);

// The first of SPEC §8's rules (1..9, in its order) that applies at `node`, or 0.
int applicable_rule(const CsgExpr& e, int node);

// One application of rule `rule` at `node` if it applies (the node is rewritten in place, so its
// parent stays valid); for tests of single rules.
bool apply_rule(CsgExpr& e, int node, int rule);

// A copy of `e` rewritten top-down until no rule applies anywhere: a union of products, each an
// ∩/− chain with primitive right operands and its ∩s before its −s. Throws Error naming the count
// when count_products() exceeds limits.max_products or the rewrites exceed limits.max_rewrites.
CsgExpr normalize_tree(const CsgExpr& e, const NormalizeLimits& limits = {});

// True when the tree is a union of ∩/− chains over primitives (in any order within a chain).
bool is_sum_of_products(const CsgExpr& e);

// The products of a sum of products, left to right, without those containing x and ¬x.
// Throws Error unless is_sum_of_products(sop).
std::vector<CsgProduct> read_products(const CsgExpr& sop);

// read_products(normalize_tree(e, limits)).
std::vector<CsgProduct> normalize(const CsgExpr& e, const NormalizeLimits& limits = {});

}  // namespace imx
