#include "csg/csg_expr.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "intermix/error.hpp"
#include "test_trees.hpp"

namespace imx {
namespace {

int leaf(CsgExpression& e, ObjectKind kind, int index, CsgPresence presence = CsgPresence::region) {
  CsgNode n;
  n.object = {kind, index};
  n.presence = presence;
  e.nodes.push_back(n);
  return int(e.nodes.size()) - 1;
}

int op(CsgExpression& e, CsgOp o, int a, int b) {
  CsgNode n;
  n.op = o;
  n.a = a;
  n.b = b;
  e.nodes.push_back(n);
  return int(e.nodes.size()) - 1;
}

std::string error_of(const CsgExpression& e) {
  std::vector<CsgPrimitive> primitives;
  try {
    compile_expression(e, primitives);
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

// Primitives are numbered by first appearance, left to right; a repeated object is one primitive.
TEST(CompileExpression, NumbersPrimitivesByFirstAppearance) {
  CsgExpression s;
  int vol2 = leaf(s, ObjectKind::volume, 2, CsgPresence::opacity);
  int mesh1 = leaf(s, ObjectKind::mesh, 1);
  int vol0 = leaf(s, ObjectKind::volume, 0);
  int mesh1_again = leaf(s, ObjectKind::mesh, 1);
  int u = op(s, CsgOp::union_of, mesh1, vol0);
  int d = op(s, CsgOp::difference, u, mesh1_again);
  s.root = op(s, CsgOp::intersection, d, vol2);
  std::vector<CsgPrimitive> primitives;
  CsgExpr e = compile_expression(s, primitives);
  EXPECT_EQ(e.primitive_count, 3);
  ASSERT_EQ(primitives.size(), 3u);
  EXPECT_EQ(primitives[0].object.kind, ObjectKind::mesh);
  EXPECT_EQ(primitives[0].object.index, 1);
  EXPECT_EQ(primitives[1].object.kind, ObjectKind::volume);
  EXPECT_EQ(primitives[1].object.index, 0);
  EXPECT_EQ(primitives[2].object.index, 2);
  EXPECT_EQ(primitives[2].presence, CsgPresence::opacity);
  EXPECT_EQ(to_string(e), "(((0 ∪ 1) − 0) ∩ 2)");
  // A mesh and a volume with the same index are different objects.
  CsgExpression t;
  t.root = op(t, CsgOp::union_of, leaf(t, ObjectKind::mesh, 0), leaf(t, ObjectKind::volume, 0));
  EXPECT_EQ(compile_expression(t, primitives).primitive_count, 2);
}

TEST(CompileExpression, RejectsTwoPresencesOfOneObject) {
  CsgExpression s;
  s.root = op(s, CsgOp::union_of, leaf(s, ObjectKind::volume, 3, CsgPresence::region),
              leaf(s, ObjectKind::volume, 3, CsgPresence::opacity));
  std::string message = error_of(s);
  EXPECT_NE(message.find("volume 3"), std::string::npos) << message;
  EXPECT_NE(message.find("both region and opacity"), std::string::npos) << message;
}

// N7: 64 distinct primitives are fine, the 65th is an error that names the limit.
TEST(CompileExpression, AtMost64Primitives) {
  for (int count : {64, 65}) {
    CsgExpression s;
    s.root = leaf(s, ObjectKind::mesh, 0);
    for (int k = 1; k < count; ++k)
      s.root = op(s, CsgOp::union_of, s.root, leaf(s, ObjectKind::mesh, k));
    std::vector<CsgPrimitive> primitives;
    if (count == 64) {
      EXPECT_EQ(compile_expression(s, primitives).primitive_count, 64);
      continue;
    }
    std::string message = error_of(s);
    EXPECT_NE(message.find("at most 64 primitives"), std::string::npos) << message;
    EXPECT_NE(message.find("65"), std::string::npos) << message;
  }
}

TEST(CompileExpression, RejectsMalformedTrees) {
  CsgExpression empty;
  EXPECT_NE(error_of(empty), "");

  CsgExpression bad_root;
  leaf(bad_root, ObjectKind::mesh, 0);
  bad_root.root = 1;
  EXPECT_NE(error_of(bad_root).find("node index 1"), std::string::npos);

  CsgExpression bad_child;
  bad_child.root = op(bad_child, CsgOp::union_of, 5, -1);
  EXPECT_NE(error_of(bad_child).find("node index 5"), std::string::npos);

  CsgExpression self_cycle;
  self_cycle.root = op(self_cycle, CsgOp::union_of, 0, 0);
  EXPECT_NE(error_of(self_cycle).find("reached twice"), std::string::npos);

  CsgExpression cycle;  // 0 -> 1 -> 0
  op(cycle, CsgOp::difference, 1, 2);
  op(cycle, CsgOp::intersection, 0, 2);
  leaf(cycle, ObjectKind::mesh, 0);
  cycle.root = 0;
  EXPECT_NE(error_of(cycle).find("reached twice"), std::string::npos);

  CsgExpression shared;
  int x = leaf(shared, ObjectKind::mesh, 0);
  shared.root = op(shared, CsgOp::union_of, x, x);
  EXPECT_NE(error_of(shared).find("reached twice"), std::string::npos);

  CsgExpression no_object;
  no_object.root = op(no_object, CsgOp::union_of, leaf(no_object, ObjectKind::mesh, 0),
                      leaf(no_object, ObjectKind::mesh, -1));
  EXPECT_NE(error_of(no_object).find("names no object"), std::string::npos);
}

TEST(CsgExprValidate, RejectsBadBuilderTrees) {
  CsgExpr e = test::expr("0|1");
  EXPECT_NO_THROW(validate(e));
  e.primitive_count = 1;  // primitive 1 is now out of range
  EXPECT_THROW(validate(e), Error);
  CsgExpr too_many;
  too_many.root = add_primitive(too_many, 64);
  EXPECT_THROW(validate(too_many), Error);
  CsgExpr dag = test::expr("0");
  dag.root = add_op(dag, CsgOp::intersection, 0, 0);
  EXPECT_THROW(validate(dag), Error);
  EXPECT_THROW(compile_program(dag), Error);
}

TEST(CsgExprToString, NumbersOrNames) {
  CsgExpr e = test::expr("(0-2)|1");
  EXPECT_EQ(to_string(e), "((0 − 2) ∪ 1)");
  std::vector<std::string> names{"skin", "bone", "ball"};
  EXPECT_EQ(to_string(e, names), "((skin − ball) ∪ bone)");
  EXPECT_EQ(to_string(e, names, e.nodes[e.root].a), "(skin − ball)");
  EXPECT_EQ(to_string(test::expr("0&(1&2)")), "(0 ∩ (1 ∩ 2))");
}

// The deepest stack the program reaches.
int stack_depth(const CsgProgram& p) {
  int depth = 0, deepest = 0;
  for (CsgInstr i : p.code) {
    depth += i.code == CsgInstr::push ? 1 : -1;
    deepest = std::max(deepest, depth);
  }
  EXPECT_EQ(depth, 1);
  return deepest;
}

TEST(CsgProgram, MatchesNaiveEvaluation) {
  std::mt19937 rng(17);
  for (int trial = 0; trial < 500; ++trial) {
    int n = 1 + int(rng() % 8);
    CsgExpr e = test::random_tree(rng, n, 7);
    CsgProgram p = compile_program(e);
    EXPECT_EQ(p.primitive_count, n);
    for (PrimitiveMask m = 0; m < (PrimitiveMask{1} << n); ++m)
      ASSERT_EQ(evaluate(p, m), test::evaluate_naive(e, m)) << to_string(e) << " at " << m;
  }
}

// A right-deep chain x0 − (x1 − (… − x255)) evaluates its right side first with the reversed
// difference, so the stack stays at 2 values.
TEST(CsgProgram, DeepRightChain) {
  CsgExpr e;
  const int leaves = 256;
  e.root = add_primitive(e, (leaves - 1) % 64);
  for (int k = leaves - 2; k >= 0; --k)
    e.root = add_op(e, CsgOp::difference, add_primitive(e, k % 64), e.root);
  CsgProgram p = compile_program(e);
  EXPECT_EQ(stack_depth(p), 2);
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    PrimitiveMask m = rng();
    bool expected = (m >> ((leaves - 1) % 64)) & 1;
    for (int k = leaves - 2; k >= 0; --k) expected = ((m >> (k % 64)) & 1) && !expected;
    ASSERT_EQ(evaluate(p, m), expected);
  }
}

TEST(CsgProgram, DeepLeftChain) {
  CsgExpr e;
  e.root = add_primitive(e, 0);
  static constexpr CsgOp ops[] = {CsgOp::union_of, CsgOp::difference, CsgOp::intersection};
  for (int k = 1; k < 256; ++k)
    e.root = add_op(e, ops[k % 3], e.root, add_primitive(e, (k * 7) % 64));
  CsgProgram p = compile_program(e);
  EXPECT_EQ(stack_depth(p), 2);
  std::mt19937_64 rng(6);
  for (int trial = 0; trial < 200; ++trial) {
    PrimitiveMask m = rng();
    bool v = m & 1;
    for (int k = 1; k < 256; ++k) {
      bool x = (m >> ((k * 7) % 64)) & 1;
      v = k % 3 == 0 ? v || x : k % 3 == 1 ? v && !x : v && x;
    }
    ASSERT_EQ(evaluate(p, m), v);
  }
}

// A balanced tree of 64 leaves needs log2(64) + 1 = 7 stack values.
TEST(CsgProgram, BalancedTreeOf64Leaves) {
  std::mt19937_64 rng(8);
  CsgExpr e;
  std::vector<int> level;
  for (int k = 0; k < 64; ++k) level.push_back(add_primitive(e, k));
  static constexpr CsgOp ops[] = {CsgOp::union_of, CsgOp::intersection, CsgOp::difference};
  while (level.size() > 1) {
    std::vector<int> next;
    for (size_t i = 0; i < level.size(); i += 2)
      next.push_back(add_op(e, ops[rng() % 3], level[i], level[i + 1]));
    level = next;
  }
  e.root = level[0];
  CsgProgram p = compile_program(e);
  EXPECT_EQ(stack_depth(p), 7);
  for (int trial = 0; trial < 2000; ++trial) {
    PrimitiveMask m = rng();
    ASSERT_EQ(evaluate(p, m), test::evaluate_naive(e, m));
  }
}

// Neither compiling nor evaluating recurses: a 100 000-deep chain is fine.
TEST(CsgProgram, VeryDeepChain) {
  CsgExpr e;
  e.root = add_primitive(e, 1);
  for (int k = 0; k < 100000; ++k)
    e.root = add_op(e, k % 2 ? CsgOp::union_of : CsgOp::intersection, add_primitive(e, 0), e.root);
  CsgProgram p = compile_program(e);
  EXPECT_EQ(stack_depth(p), 2);
  EXPECT_TRUE(evaluate(p, 0b01));   // the outermost ∪ holds with 0 present
  EXPECT_FALSE(evaluate(p, 0b10));  // every ∩ needs 0
  EXPECT_FALSE(evaluate(p, 0));
}

}  // namespace
}  // namespace imx
