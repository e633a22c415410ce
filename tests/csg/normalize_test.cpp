#include "csg/normalize.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <set>
#include <string>

#include "intermix/error.hpp"
#include "test_trees.hpp"

namespace imx {
namespace {

std::string error_of(const CsgExpr& e, const NormalizeLimits& limits = {}) {
  try {
    normalize(e, limits);
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

void expect_same_truth_table(const CsgExpr& a, const CsgExpr& b, int n) {
  for (PrimitiveMask m = 0; m < (PrimitiveMask{1} << n); ++m)
    EXPECT_EQ(test::evaluate_naive(a, m), test::evaluate_naive(b, m))
        << to_string(a) << " vs " << to_string(b) << " at " << m;
}

struct RuleCase {
  int rule;
  const char* lhs;
  const char* rhs;
};

// SPEC §8's rules in its order, on x = 0, y = 1, z = 2.
const RuleCase kRules[] = {
    {1, "0-(1|2)", "((0 − 1) − 2)"},       {2, "0&(1|2)", "((0 ∩ 1) ∪ (0 ∩ 2))"},
    {3, "0-(1&2)", "((0 − 1) ∪ (0 − 2))"}, {4, "0&(1&2)", "((0 ∩ 1) ∩ 2)"},
    {5, "0-(1-2)", "((0 − 1) ∪ (0 ∩ 2))"}, {6, "0&(1-2)", "((0 ∩ 1) − 2)"},
    {7, "(0-1)&2", "((0 ∩ 2) − 1)"},       {8, "(0|1)-2", "((0 − 2) ∪ (1 − 2))"},
    {9, "(0|1)&2", "((0 ∩ 2) ∪ (1 ∩ 2))"},
};

// N1: each rule, applied once at the root, keeps the truth table and gives SPEC's right-hand side;
// no other rule matches its left-hand side.
TEST(NormalizeRules, EachRuleOnce) {
  for (const RuleCase& c : kRules) {
    SCOPED_TRACE(c.rule);
    CsgExpr lhs = test::expr(c.lhs);
    EXPECT_EQ(applicable_rule(lhs, lhs.root), c.rule);
    for (int other = 1; other <= 9; ++other) {
      if (other == c.rule) continue;
      CsgExpr copy = lhs;
      EXPECT_FALSE(apply_rule(copy, copy.root, other)) << "rule " << other;
      EXPECT_EQ(to_string(copy), to_string(lhs));
    }
    CsgExpr rhs = lhs;
    ASSERT_TRUE(apply_rule(rhs, rhs.root, c.rule));
    EXPECT_EQ(to_string(rhs), c.rhs);
    expect_same_truth_table(lhs, rhs, 3);
  }
}

// The same with compound operands: the duplicated operand is copied (the result stays a tree).
TEST(NormalizeRules, CompoundOperandsAreCopied) {
  for (const RuleCase& c : kRules) {
    SCOPED_TRACE(c.rule);
    std::string text;
    for (const char* p = c.lhs; *p; ++p)
      text += *p == '0' ? "(3-4)" : *p == '1' ? "(5&0)" : *p == '2' ? "(1|6)" : std::string(1, *p);
    CsgExpr lhs = test::expr(text), rhs = lhs;
    ASSERT_TRUE(apply_rule(rhs, rhs.root, c.rule));
    EXPECT_NO_THROW(validate(rhs));
    std::string shaped;
    for (char ch : std::string(c.rhs))
      shaped += ch == '0'   ? "(3 − 4)"
                : ch == '1' ? "(5 ∩ 0)"
                : ch == '2' ? "(1 ∪ 6)"
                            : std::string(1, ch);
    EXPECT_EQ(to_string(rhs), shaped);
    expect_same_truth_table(lhs, rhs, 7);
  }
}

TEST(Normalize, FixedPointIsCanonicalSumOfProducts) {
  CsgExpr e = test::expr("((0|1)-(2&3))&(4-(5|6))");
  CsgExpr sop = normalize_tree(e);
  EXPECT_TRUE(is_sum_of_products(sop));
  EXPECT_FALSE(is_sum_of_products(e));
  expect_same_truth_table(e, sop, 7);
  EXPECT_EQ(read_products(sop).size(), count_products(e));
  EXPECT_THROW(read_products(e), Error);
}

// N3: the seed's corrected worked example (a∪b)−(c∩d) gives a−c, b−c, a−d, b−d.
TEST(Normalize, WorkedExample) {
  std::vector<CsgProduct> p = normalize(test::expr("(0|1)-(2&3)"));
  std::vector<CsgProduct> expected{
      {0b0001, 0b0100}, {0b0010, 0b0100}, {0b0001, 0b1000}, {0b0010, 0b1000}};
  EXPECT_EQ(p, expected);
}

TEST(Normalize, RepeatedPrimitives) {
  EXPECT_TRUE(normalize(test::expr("0-0")).empty());  // x ∧ ¬x
  EXPECT_EQ(normalize(test::expr("((0&1)&2)&0")), (std::vector<CsgProduct>{{0b111, 0}}));
  EXPECT_EQ(normalize(test::expr("0")), (std::vector<CsgProduct>{{1, 0}}));
}

// N4: the chain the seed's literal pseudo-code can leave, (x−y)∩z, still reads as x ∧ ¬y ∧ z.
TEST(Normalize, ChainInAnyOrder) {
  CsgExpr chain = test::expr("(0-1)&2");
  EXPECT_TRUE(is_sum_of_products(chain));
  EXPECT_EQ(read_products(chain), (std::vector<CsgProduct>{{0b101, 0b010}}));
  EXPECT_EQ(normalize(chain), read_products(chain));
  CsgExpr longer = test::expr("(((0-1)&2)-3)&4");
  EXPECT_EQ(read_products(longer), (std::vector<CsgProduct>{{0b10101, 0b01010}}));
}

// (a1∪b1) ∩ (a2∪b2) ∩ … ∩ (ak∪bk) over primitives 2j, 2j+1 (0 and 1 repeat when k > 32).
CsgExpr intersection_of_pairs(int k) {
  CsgExpr e;
  auto pair = [&](int j) {
    return add_op(e, CsgOp::union_of, add_primitive(e, 2 * j % 64),
                  add_primitive(e, (2 * j + 1) % 64));
  };
  e.root = pair(0);
  for (int j = 1; j < k; ++j) e.root = add_op(e, CsgOp::intersection, e.root, pair(j));
  return e;
}

// N5: 2^k products, one of a_j, b_j each.
TEST(NormalizeBlowUp, TwoToTheKProducts) {
  for (int k = 1; k <= 10; ++k) {
    std::vector<CsgProduct> p = normalize(intersection_of_pairs(k));
    ASSERT_EQ(p.size(), size_t{1} << k);
    std::set<PrimitiveMask> distinct;
    for (CsgProduct q : p) {
      EXPECT_EQ(q.neg, 0u);
      for (int j = 0; j < k; ++j) EXPECT_EQ(std::popcount((q.pos >> 2 * j) & 3), 1);
      distinct.insert(q.pos);
    }
    EXPECT_EQ(distinct.size(), p.size());
  }
}

TEST(NormalizeBlowUp, ErrorNamesTheCount) {
  std::string message = error_of(intersection_of_pairs(13));
  EXPECT_NE(message.find("8192 products"), std::string::npos) << message;
  EXPECT_NE(message.find("render.csg_max_states = 4096"), std::string::npos) << message;
  EXPECT_EQ(error_of(intersection_of_pairs(12)), "");
  NormalizeLimits small{100, 1'000'000};
  EXPECT_NE(error_of(intersection_of_pairs(7), small).find("128 products"), std::string::npos);
}

// The count comes from the tree's shape, so even 2^32 or a saturated count fails at once.
TEST(NormalizeBlowUp, FailsBeforeExponentialWork) {
  auto start = std::chrono::steady_clock::now();
  EXPECT_NE(error_of(intersection_of_pairs(32)).find("4294967296 products"), std::string::npos);
  EXPECT_NE(error_of(intersection_of_pairs(70)).find("over 18446744073709551615"),
            std::string::npos);
  CsgExpr difference_chain = test::expr("0");  // 0 − (1∩2) − (3∩4) − …: 2^k products too
  for (int j = 0; j < 30; ++j)
    difference_chain.root = add_op(
        difference_chain, CsgOp::difference, difference_chain.root,
        add_op(difference_chain, CsgOp::intersection, add_primitive(difference_chain, 2 * j + 1),
               add_primitive(difference_chain, 2 * j + 2)));
  EXPECT_EQ(count_products(difference_chain), uint64_t{1} << 30);
  EXPECT_NE(error_of(difference_chain).find("1073741824 products"), std::string::npos);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
}

// A few products but a long right-deep chain: the rewrite budget stops it with an error.
TEST(NormalizeBlowUp, RewriteBudget) {
  CsgExpr e = test::expr("(0|1|2|3|4|5|6|7)");
  int union_root = e.root;
  int chain = add_primitive(e, 8 + 0);
  for (int k = 1; k < 100000; ++k)
    chain = add_op(e, CsgOp::intersection, add_primitive(e, 8 + k % 56), chain);
  e.root = add_op(e, CsgOp::intersection, union_root, chain);
  EXPECT_EQ(count_products(e), 8u);
  auto start = std::chrono::steady_clock::now();
  std::string message = error_of(e);
  EXPECT_NE(message.find("more than 1000000 rewrite steps"), std::string::npos) << message;
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
  message = error_of(test::expr("0&(1&(2&(3&(4&5))))"), {4096, 3});
  EXPECT_NE(message.find("more than 3 rewrite steps"), std::string::npos) << message;
  // Within the default budget a long chain of one product normalizes, without recursion.
  CsgExpr single = test::expr("0-1");
  for (int k = 0; k < 20000; ++k)
    single.root =
        add_op(single, CsgOp::intersection, add_primitive(single, 2 + k % 60), single.root);
  std::vector<CsgProduct> p = normalize(single);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0], (CsgProduct{low_primitives(62) & ~PrimitiveMask{2}, 2}));
}

}  // namespace
}  // namespace imx
