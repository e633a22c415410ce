#include "csg/normalize.hpp"

#include <limits>
#include <utility>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx {
namespace {

constexpr uint64_t kSaturated = std::numeric_limits<uint64_t>::max();

uint64_t add_sat(uint64_t a, uint64_t b) {
  uint64_t r;
  return __builtin_add_overflow(a, b, &r) ? kSaturated : r;
}

uint64_t mul_sat(uint64_t a, uint64_t b) {
  uint64_t r;
  return __builtin_mul_overflow(a, b, &r) ? kSaturated : r;
}

bool is_chain_op(CsgOp op) {
  return op == CsgOp::intersection || op == CsgOp::difference;
}

void set(CsgExpr& e, int node, CsgOp op, int a, int b) {
  e.nodes[node] = {op, -1, a, b};
}

// A copy of the subtree at `node`, made without recursion; returns its root.
int copy_subtree(CsgExpr& e, int node) {
  int root = -1;
  struct Item {
    int source, parent;
    bool left;
  };
  std::vector<Item> stack{{node, -1, true}};
  while (!stack.empty()) {
    Item item = stack.back();
    stack.pop_back();
    CsgExpr::Node n = e.nodes[item.source];
    int index = int(e.nodes.size());
    e.nodes.push_back(n);
    if (item.parent < 0)
      root = index;
    else
      (item.left ? e.nodes[item.parent].a : e.nodes[item.parent].b) = index;
    if (n.op != CsgOp::primitive) {
      stack.push_back({n.b, index, false});
      stack.push_back({n.a, index, true});
    }
  }
  return root;
}

// Applies rule `rule`, known to match at `node`; returns the number of nodes it copied. The
// matched child node is reused for the first new operand, so nothing becomes garbage.
long rewrite(CsgExpr& e, int node, int rule) {
  const CsgOp I = CsgOp::intersection, D = CsgOp::difference, U = CsgOp::union_of;
  size_t before = e.nodes.size();
  CsgExpr::Node n = e.nodes[node];
  if (rule <= 6) {  // x ⊙ (y ⊙ z), R = (y ⊙ z)
    int x = n.a, r = n.b, y = e.nodes[r].a, z = e.nodes[r].b;
    switch (rule) {
      case 1:  // (x−y)−z
      case 4:  // (x∩y)∩z
      case 6:  // (x∩y)−z
        set(e, r, rule == 1 ? D : I, x, y);
        set(e, node, rule == 4 ? I : D, r, z);
        break;
      default: {  // 2: (x∩y)∪(x∩z); 3: (x−y)∪(x−z); 5: (x−y)∪(x∩z)
        CsgOp first = rule == 2 ? I : D, second = rule == 3 ? D : I;
        int x2 = copy_subtree(e, x);
        set(e, r, first, x, y);
        set(e, node, U, r, add_op(e, second, x2, z));
      }
    }
  } else {  // (x ⊙ y) ⊙ z, L = (x ⊙ y)
    int l = n.a, z = n.b, x = e.nodes[l].a, y = e.nodes[l].b;
    if (rule == 7) {  // (x∩z)−y
      set(e, l, I, x, z);
      set(e, node, D, l, y);
    } else {  // 8: (x−z)∪(y−z); 9: (x∩z)∪(y∩z)
      int z2 = copy_subtree(e, z);
      set(e, l, n.op, x, z);
      set(e, node, U, l, add_op(e, n.op, y, z2));
    }
  }
  return long(e.nodes.size() - before);
}

bool rule_matches(const CsgExpr& e, int node, int rule) {
  const CsgExpr::Node& n = e.nodes[node];
  if (!is_chain_op(n.op)) return false;
  bool meet = n.op == CsgOp::intersection;
  CsgOp l = e.nodes[n.a].op, r = e.nodes[n.b].op;
  switch (rule) {
    case 1:
      return !meet && r == CsgOp::union_of;
    case 2:
      return meet && r == CsgOp::union_of;
    case 3:
      return !meet && r == CsgOp::intersection;
    case 4:
      return meet && r == CsgOp::intersection;
    case 5:
      return !meet && r == CsgOp::difference;
    case 6:
      return meet && r == CsgOp::difference;
    case 7:
      return meet && l == CsgOp::difference;
    case 8:
      return !meet && l == CsgOp::union_of;
    case 9:
      return meet && l == CsgOp::union_of;
  }
  return false;
}

// Walks a sum of products; appends its products to `out` (if given, contradictions included).
bool walk_products(const CsgExpr& e, std::vector<CsgProduct>* out) {
  std::vector<int> unions{e.root};
  while (!unions.empty()) {
    int node = unions.back();
    unions.pop_back();
    if (e.nodes[node].op == CsgOp::union_of) {
      unions.push_back(e.nodes[node].b);
      unions.push_back(e.nodes[node].a);
      continue;
    }
    CsgProduct p;
    for (; is_chain_op(e.nodes[node].op); node = e.nodes[node].a) {
      const CsgExpr::Node& operand = e.nodes[e.nodes[node].b];
      if (operand.op != CsgOp::primitive) return false;
      (e.nodes[node].op == CsgOp::intersection ? p.pos : p.neg) |= PrimitiveMask{1}
                                                                   << operand.primitive;
    }
    if (e.nodes[node].op != CsgOp::primitive) return false;
    p.pos |= PrimitiveMask{1} << e.nodes[node].primitive;
    if (out) out->push_back(p);
  }
  return true;
}

}  // namespace

uint64_t count_products(const CsgExpr& e) {
  validate(e);
  // p: products of the subtree; q: products of its complement (¬(a−b) = ¬a ∪ b, etc.). Only p of
  // a node on the left of − is ever rewritten, and every rule keeps p, so p(root) is exact.
  std::vector<std::pair<uint64_t, uint64_t>> pq(e.nodes.size(), {1, 1});
  std::vector<std::pair<int, bool>> walk{{e.root, false}};
  while (!walk.empty()) {
    auto [node, children_done] = walk.back();
    walk.pop_back();
    const CsgExpr::Node& n = e.nodes[node];
    if (n.op == CsgOp::primitive) continue;
    if (!children_done) {
      walk.push_back({node, true});
      walk.push_back({n.a, false});
      walk.push_back({n.b, false});
      continue;
    }
    auto [pa, qa] = pq[n.a];
    auto [pb, qb] = pq[n.b];
    pq[node] = n.op == CsgOp::union_of       ? std::pair{add_sat(pa, pb), mul_sat(qa, qb)}
               : n.op == CsgOp::intersection ? std::pair{mul_sat(pa, pb), add_sat(qa, qb)}
                                             : std::pair{mul_sat(pa, qb), add_sat(qa, pb)};
  }
  return pq[e.root].first;
}

int applicable_rule(const CsgExpr& e, int node) {
  for (int rule = 1; rule <= 9; ++rule)
    if (rule_matches(e, node, rule)) return rule;
  return 0;
}

bool apply_rule(CsgExpr& e, int node, int rule) {
  validate(e);
  if (node < 0 || size_t(node) >= e.nodes.size() || !rule_matches(e, node, rule)) return false;
  rewrite(e, node, rule);
  return true;
}

CsgExpr normalize_tree(const CsgExpr& e, const NormalizeLimits& limits) {
  uint64_t products = count_products(e);
  if (products > uint64_t(limits.max_products))
    throw Error(
        fmt::format("the CSG expression expands to {}{} products, more than "
                    "render.csg_max_states = {}; nested ∩ of ∪ and − of ∩ grow as 2^k",
                    products == kSaturated ? "over " : "", products, limits.max_products));
  CsgExpr t = e;
  long steps = 0;
  // Top-down (Goldfeather): rewrite a node until no rule applies, normalize its left operand,
  // re-check the node (the left side may now be a ∪ or a − chain), then its right operand.
  // stage 0: rewrite the node; 1: the left operand is done; 2: the right one is done.
  // Finished subtrees are flagged so that re-checks after a rewrite do not walk them again
  // (that would be quadratic in long chains); a rewrite changes only its node and operand a.
  std::vector<char> done(t.nodes.size(), 0);
  std::vector<std::pair<int, int>> stack{{t.root, 0}};
  auto descend = [&](int node) {
    if (!done[node]) stack.push_back({node, 0});
  };
  while (!stack.empty()) {
    auto [node, stage] = stack.back();
    if (stage == 0) {
      for (int rule; (rule = applicable_rule(t, node)) != 0;) {
        steps += 1 + rewrite(t, node, rule);
        if (steps > limits.max_rewrites)
          throw Error(
              fmt::format("normalizing the CSG expression takes more than {} rewrite "
                          "steps; simplify the expression",
                          limits.max_rewrites));
        done.resize(t.nodes.size(), 0);
        done[t.nodes[node].a] = 0;
      }
      if (t.nodes[node].op == CsgOp::primitive) {
        done[node] = 1;
        stack.pop_back();
        continue;
      }
      stack.back().second = 1;
      descend(t.nodes[node].a);
    } else if (stage == 1) {
      if (applicable_rule(t, node) != 0) {
        stack.back().second = 0;
        continue;
      }
      stack.back().second = 2;
      descend(t.nodes[node].b);
    } else {
      done[node] = 1;
      stack.pop_back();
    }
  }
  return t;
}

bool is_sum_of_products(const CsgExpr& e) {
  validate(e);
  return walk_products(e, nullptr);
}

std::vector<CsgProduct> read_products(const CsgExpr& sop) {
  validate(sop);
  std::vector<CsgProduct> all;
  if (!walk_products(sop, &all))
    throw Error(fmt::format("read_products: {} is not a union of ∩/− chains", to_string(sop)));
  std::vector<CsgProduct> out;
  for (CsgProduct p : all)
    if ((p.pos & p.neg) == 0) out.push_back(p);
  return out;
}

std::vector<CsgProduct> normalize(const CsgExpr& e, const NormalizeLimits& limits) {
  return read_products(normalize_tree(e, limits));
}

}  // namespace imx
