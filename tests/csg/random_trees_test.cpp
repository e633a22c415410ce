#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "csg/state_table.hpp"
#include "intermix/error.hpp"
#include "test_trees.hpp"

namespace imx {
namespace {

// Every reachable node of a tree (the tests' trees are small).
std::vector<int> reachable(const CsgExpr& e) {
  std::vector<int> out, stack{e.root};
  while (!stack.empty()) {
    int n = stack.back();
    stack.pop_back();
    out.push_back(n);
    if (e.nodes[n].op != CsgOp::primitive) {
      stack.push_back(e.nodes[n].a);
      stack.push_back(e.nodes[n].b);
    }
  }
  return out;
}

// No other state matches some non-empty assignment that `s` matches, and widening any of its
// digits to 2 would match a non-empty assignment where E is false: a prime, not redundant.
void expect_prime_and_needed(const CsgProgram& p, const std::vector<ClipState>& states, int n) {
  PrimitiveMask all = PrimitiveMask{1} << n;
  for (ClipState s : states) {
    bool needed = false;
    for (PrimitiveMask m = 1; m < all; ++m) {
      if (!matches(s, m)) continue;
      int matching = 0;
      for (ClipState t : states) matching += matches(t, m);
      needed |= matching == 1;
    }
    EXPECT_TRUE(needed) << digits(s, n) << " is redundant";
    for (int k = 0; k < n; ++k) {
      PrimitiveMask bit = PrimitiveMask{1} << k;
      if (!((s.ones | s.zeros) & bit)) continue;
      ClipState wider{s.ones & ~bit, s.zeros & ~bit};
      bool still_implicant = true;
      for (PrimitiveMask m = 1; m < all; ++m)
        if (matches(wider, m) && !evaluate(p, m)) still_implicant = false;
      EXPECT_FALSE(still_implicant) << digits(s, n) << " is not prime in digit " << k;
    }
  }
}

// N2: 2000 random trees through the whole pipeline, checked on every assignment.
TEST(RandomTrees, PipelineMatchesEvaluate) {
  std::mt19937 rng(2024);
  int checked = 0, over_cap = 0;
  while (checked < 2000) {
    int n = 1 + int(rng() % 8);
    CsgExpr e = test::random_tree(rng, n, 1 + int(rng() % 7));
    CsgProgram program = compile_program(e);
    CsgExpr sop;
    try {
      sop = normalize_tree(e);
    } catch (const Error&) {
      ++over_cap;
      EXPECT_GT(count_products(e), 4096u) << to_string(e);
      continue;
    }
    ++checked;
    SCOPED_TRACE(to_string(e));
    ASSERT_TRUE(is_sum_of_products(sop));
    int unions = 0;
    for (int node : reachable(sop)) {
      EXPECT_EQ(applicable_rule(sop, node), 0) << "not a fixed point at node " << node;
      unions += sop.nodes[node].op == CsgOp::union_of;
    }
    EXPECT_EQ(uint64_t(unions) + 1, count_products(e));
    CsgProgram sop_program = compile_program(sop);
    std::vector<CsgProduct> products = read_products(sop);
    CsgTable none = build_table(products, n, 0, CsgSimplify::none, {}, 4096);
    CsgTable merged = build_table(products, n, 0, CsgSimplify::merge, {}, 4096);
    CsgTable full = build_table(products, n, 0, CsgSimplify::full, {}, 4096);
    EXPECT_LE(merged.states.size(), none.states.size());
    EXPECT_LE(full.states.size(), merged.states.size());
    EXPECT_FALSE(evaluate(program, 0));
    for (PrimitiveMask m = 0; m < (PrimitiveMask{1} << n); ++m) {
      bool expected = test::evaluate_naive(e, m);
      ASSERT_EQ(evaluate(program, m), expected) << m;
      ASSERT_EQ(evaluate(sop_program, m), expected) << m;
      ASSERT_EQ(test::any_product(products, m), expected) << m;
      ASSERT_EQ(matches_any(none.states, m), expected) << m;
      ASSERT_EQ(matches_any(merged.states, m), expected) << m;
      if (m != 0) {
        ASSERT_EQ(matches_any(full.states, m), expected) << m;
      }
    }
    expect_prime_and_needed(program, full.states, n);
  }
  EXPECT_LT(over_cap, 200);
}

// Random boxes: a presence pattern m can occur only where the boxes of all of m meet; there the
// pruned tables must still equal the expression.
TEST(RandomTrees, PrunedTablesAgreeWhereBoxesAllow) {
  std::mt19937 rng(77);
  int checked = 0, pruned = 0;
  while (checked < 1000) {
    int n = 1 + int(rng() % 8);
    CsgExpr e = test::random_tree(rng, n, 1 + int(rng() % 6));
    std::vector<CsgProduct> products;
    try {
      products = normalize(e);
    } catch (const Error&) {
      continue;
    }
    ++checked;
    std::vector<CsgBox> boxes(n);
    for (CsgBox& b : boxes)
      for (int axis = 0; axis < 3; ++axis) {
        b.lo[axis] = double(rng() % 5);
        b.hi[axis] = b.lo[axis] + double(rng() % 3);
      }
    CsgProgram program = compile_program(e);
    CsgTableReport report;
    CsgTable merged = build_table(products, n, 0, CsgSimplify::merge, boxes, 4096, &report);
    CsgTable full = build_table(products, n, 0, CsgSimplify::full, boxes, 4096);
    pruned += !report.pruned.empty();
    for (PrimitiveMask m = 0; m < (PrimitiveMask{1} << n); ++m) {
      CsgBox common{glm::dvec3(-INFINITY), glm::dvec3(INFINITY)};
      for (int k = 0; k < n; ++k)
        if (m >> k & 1) {
          common.lo = glm::max(common.lo, boxes[k].lo);
          common.hi = glm::min(common.hi, boxes[k].hi);
        }
      if (common.lo.x > common.hi.x || common.lo.y > common.hi.y || common.lo.z > common.hi.z)
        continue;  // cannot occur anywhere
      bool expected = evaluate(program, m);
      ASSERT_EQ(matches_any(merged.states, m), expected) << to_string(e) << " at " << m;
      if (m != 0) {
        ASSERT_EQ(matches_any(full.states, m), expected) << to_string(e) << " at " << m;
      }
    }
  }
  EXPECT_GT(pruned, 100);  // the boxes did prune something
}

// SPEC §8's interval rule is exact for every table: an interval inside `inside` is accepted iff
// some presence m could make a visible sample there (geometric primitives are present wherever
// they are inside, opacity ones may or may not be), as acceptance_proto.py checks.
TEST(RandomTrees, IntervalAcceptanceIsExact) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 600; ++trial) {
    int n = 1 + int(rng() % 4);
    CsgExpr e = test::random_tree(rng, n, 1 + int(rng() % 5));
    std::vector<CsgProduct> products = normalize(e);
    CsgProgram program = compile_program(e);
    PrimitiveMask used = low_primitives(n);
    for (CsgSimplify level : {CsgSimplify::none, CsgSimplify::merge, CsgSimplify::full}) {
      CsgTable t = build_table(products, n, 0, level, {}, 4096);
      for (PrimitiveMask g = 0; g <= used; ++g) {
        t.geometric = g;
        for (PrimitiveMask inside = 0; inside <= used; ++inside) {
          bool visible_somewhere = false;
          for (PrimitiveMask m = 1; m <= used; ++m)
            if ((m & ~inside) == 0 && (m & g) == (inside & g) && evaluate(program, m))
              visible_somewhere = true;
          ASSERT_EQ(may_accept_any(t.states, inside, t.geometric, t.used), visible_somewhere)
              << to_string(e) << " inside " << inside << " geometric " << g;
        }
      }
    }
  }
}

}  // namespace
}  // namespace imx
