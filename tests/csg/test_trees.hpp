// Test helpers for the csg tests: expressions from text, seeded random trees, reference evaluation.
#pragma once
#include <cctype>
#include <random>
#include <span>
#include <stdexcept>
#include <string_view>

#include "csg/csg_expr.hpp"
#include "csg/normalize.hpp"

namespace imx::test {

// Parses "(0-1)|(0&1)": primitive numbers, | & - (left-associative, one precedence), parentheses.
class ExprParser {
 public:
  explicit ExprParser(std::string_view text) : text_(text) {}
  CsgExpr parse() {
    e_.root = expression();
    if (pos_ != text_.size()) throw std::invalid_argument("trailing text");
    return e_;
  }

 private:
  int expression() {
    int left = operand();
    while (pos_ < text_.size() && text_[pos_] != ')') {
      char c = text_[pos_++];
      CsgOp op = c == '|'   ? CsgOp::union_of
                 : c == '&' ? CsgOp::intersection
                 : c == '-' ? CsgOp::difference
                            : throw std::invalid_argument("bad operator");
      left = add_op(e_, op, left, operand());
    }
    return left;
  }
  int operand() {
    if (pos_ < text_.size() && text_[pos_] == '(') {
      ++pos_;
      int inner = expression();
      if (pos_ >= text_.size() || text_[pos_++] != ')') throw std::invalid_argument("no ')'");
      return inner;
    }
    int k = 0;
    size_t start = pos_;
    while (pos_ < text_.size() && std::isdigit(static_cast<unsigned char>(text_[pos_])))
      k = 10 * k + (text_[pos_++] - '0');
    if (pos_ == start) throw std::invalid_argument("expected a primitive");
    return add_primitive(e_, k);
  }
  std::string_view text_;
  size_t pos_ = 0;
  CsgExpr e_;
};

inline CsgExpr expr(std::string_view text) {
  return ExprParser(text).parse();
}

// Like the prototypes' rand_tree: a leaf at depth 0 or with probability 1/4, else a random
// operator over two random subtrees. Leaves repeat freely.
inline int add_random_tree(CsgExpr& e, std::mt19937& rng, int primitives, int depth) {
  if (depth == 0 || rng() % 4 == 0) return add_primitive(e, int(rng() % primitives));
  static constexpr CsgOp ops[] = {CsgOp::union_of, CsgOp::intersection, CsgOp::difference};
  CsgOp op = ops[rng() % 3];
  int a = add_random_tree(e, rng, primitives, depth - 1);
  int b = add_random_tree(e, rng, primitives, depth - 1);
  return add_op(e, op, a, b);
}

inline CsgExpr random_tree(std::mt19937& rng, int primitives, int depth) {
  CsgExpr e;
  e.root = add_random_tree(e, rng, primitives, depth);
  e.primitive_count = primitives;
  return e;
}

// Plain recursive evaluation (shallow test trees only): the oracle for the postfix program.
inline bool evaluate_naive(const CsgExpr& e, int node, PrimitiveMask present) {
  const CsgExpr::Node& n = e.nodes[node];
  if (n.op == CsgOp::primitive) return (present >> n.primitive) & 1;
  bool a = evaluate_naive(e, n.a, present), b = evaluate_naive(e, n.b, present);
  return n.op == CsgOp::union_of ? a || b : n.op == CsgOp::intersection ? a && b : a && !b;
}

inline bool evaluate_naive(const CsgExpr& e, PrimitiveMask present) {
  return evaluate_naive(e, e.root, present);
}

// Some product holds where exactly `present` is present.
inline bool any_product(std::span<const CsgProduct> products, PrimitiveMask present) {
  for (CsgProduct p : products)
    if ((p.pos & ~present) == 0 && (p.neg & present) == 0) return true;
  return false;
}

}  // namespace imx::test
