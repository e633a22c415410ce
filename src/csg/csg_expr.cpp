#include "csg/csg_expr.hpp"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx {
namespace {

const char* presence_name(CsgPresence p) {
  return p == CsgPresence::region ? "region" : "opacity";
}

const char* op_symbol(CsgOp op) {
  return op == CsgOp::union_of ? " ∪ " : op == CsgOp::intersection ? " ∩ " : " − ";
}

bool is_operator(CsgOp op) {
  return op == CsgOp::union_of || op == CsgOp::intersection || op == CsgOp::difference;
}

// Marks `node` reached; a second arrival means a shared node or a cycle.
void reach(std::vector<char>& reached, int node, size_t count, const char* what) {
  if (node < 0 || size_t(node) >= count)
    throw Error(fmt::format("{}: node index {} is outside 0..{}", what, node, count - 1));
  if (reached[node])
    throw Error(
        fmt::format("{}: node {} is reached twice (a shared node or a cycle); the "
                    "expression must be a tree",
                    what, node));
  reached[node] = 1;
}

}  // namespace

CsgExpr compile_expression(const CsgExpression& e, std::vector<CsgPrimitive>& primitives) {
  const char* what = "csg expression";
  if (e.nodes.empty()) throw Error("csg expression has no nodes");
  primitives.clear();
  CsgExpr out;
  std::vector<char> reached(e.nodes.size(), 0);
  // Pre-order with the left operand first numbers primitives by first appearance.
  struct Item {
    int source, parent;
    bool left;
  };
  std::vector<Item> stack{{e.root, -1, true}};
  while (!stack.empty()) {
    Item item = stack.back();
    stack.pop_back();
    reach(reached, item.source, e.nodes.size(), what);
    const CsgNode& n = e.nodes[item.source];
    int index = int(out.nodes.size());
    out.nodes.push_back({n.op, -1, -1, -1});
    if (item.parent < 0)
      out.root = index;
    else
      (item.left ? out.nodes[item.parent].a : out.nodes[item.parent].b) = index;
    if (is_operator(n.op)) {
      stack.push_back({n.b, index, false});
      stack.push_back({n.a, index, true});
      continue;
    }
    if (n.op != CsgOp::primitive)
      throw Error(fmt::format("{}: node {} has an unknown operator", what, item.source));
    if (n.object.index < 0)
      throw Error(fmt::format("{}: leaf node {} names no object", what, item.source));
    int k = 0;
    while (k < int(primitives.size()) && (primitives[k].object.kind != n.object.kind ||
                                          primitives[k].object.index != n.object.index))
      ++k;
    if (k == int(primitives.size())) {
      if (k == kMaxCsgPrimitives)
        throw Error(
            fmt::format("{}: at most {} primitives are allowed; node {} ({} {}) would be "
                        "primitive number {}",
                        what, kMaxCsgPrimitives, item.source, object_kind_name(n.object.kind),
                        n.object.index, k + 1));
      primitives.push_back({n.object, n.presence});
    } else if (primitives[k].presence != n.presence) {
      throw Error(fmt::format("{}: {} {} is used with both {} and {} presence", what,
                              object_kind_name(n.object.kind), n.object.index,
                              presence_name(primitives[k].presence), presence_name(n.presence)));
    }
    out.nodes[index].primitive = k;
  }
  out.primitive_count = int(primitives.size());
  return out;
}

void validate(const CsgExpr& e) {
  const char* what = "CsgExpr";
  if (e.primitive_count < 0 || e.primitive_count > kMaxCsgPrimitives)
    throw Error(fmt::format("{}: {} primitives, at most {} are allowed", what, e.primitive_count,
                            kMaxCsgPrimitives));
  if (e.nodes.empty()) throw Error("CsgExpr has no nodes");
  std::vector<char> reached(e.nodes.size(), 0);
  std::vector<int> stack{e.root};
  while (!stack.empty()) {
    int node = stack.back();
    stack.pop_back();
    reach(reached, node, e.nodes.size(), what);
    const CsgExpr::Node& n = e.nodes[node];
    if (is_operator(n.op)) {
      stack.push_back(n.b);
      stack.push_back(n.a);
    } else if (n.op != CsgOp::primitive) {
      throw Error(fmt::format("{}: node {} has an unknown operator", what, node));
    } else if (n.primitive < 0 || n.primitive >= e.primitive_count) {
      throw Error(fmt::format("{}: node {} is primitive {}, outside 0..{}", what, node, n.primitive,
                              e.primitive_count - 1));
    }
  }
}

int add_primitive(CsgExpr& e, int primitive) {
  e.nodes.push_back({CsgOp::primitive, primitive, -1, -1});
  e.primitive_count = std::max(e.primitive_count, primitive + 1);
  return int(e.nodes.size()) - 1;
}

int add_op(CsgExpr& e, CsgOp op, int a, int b) {
  e.nodes.push_back({op, -1, a, b});
  return int(e.nodes.size()) - 1;
}

std::string to_string(const CsgExpr& e, int node) {
  return to_string(e, {}, node);
}

std::string to_string(const CsgExpr& e, std::span<const std::string> names, int node) {
  validate(e);
  if (node >= int(e.nodes.size()))
    throw Error(fmt::format("to_string: node {} is outside 0..{}", node, e.nodes.size() - 1));
  std::string out;
  // Explicit stack: stage 0 opens a node, 1 sits between its operands, 2 closes it.
  std::vector<std::pair<int, int>> stack{{node < 0 ? e.root : node, 0}};
  while (!stack.empty()) {
    auto& [n, stage] = stack.back();
    const CsgExpr::Node& x = e.nodes[n];
    if (x.op == CsgOp::primitive) {
      out += x.primitive < int(names.size()) ? names[x.primitive] : std::to_string(x.primitive);
      stack.pop_back();
    } else if (stage == 0) {
      out += '(';
      stage = 1;
      stack.push_back({x.a, 0});
    } else if (stage == 1) {
      out += op_symbol(x.op);
      stage = 2;
      stack.push_back({x.b, 0});
    } else {
      out += ')';
      stack.pop_back();
    }
  }
  return out;
}

CsgProgram compile_program(const CsgExpr& e) {
  validate(e);
  // Sethi–Ullman numbers: the stack depth a subtree needs when its deeper operand goes first.
  std::vector<int> need(e.nodes.size(), 1);
  std::vector<std::pair<int, bool>> walk{{e.root, false}};
  while (!walk.empty()) {
    auto [n, children_done] = walk.back();
    walk.pop_back();
    const CsgExpr::Node& x = e.nodes[n];
    if (x.op == CsgOp::primitive) continue;
    if (!children_done) {
      walk.push_back({n, true});
      walk.push_back({x.a, false});
      walk.push_back({x.b, false});
    } else {
      int na = need[x.a], nb = need[x.b];
      need[n] = na == nb ? na + 1 : std::max(na, nb);
    }
  }
  if (need[e.root] > 64)
    throw Error(fmt::format("CSG program needs a stack of {} values, more than 64", need[e.root]));

  CsgProgram p;
  p.primitive_count = e.primitive_count;
  std::vector<std::pair<int, int>> stack{{e.root, 0}};
  while (!stack.empty()) {
    auto& [n, stage] = stack.back();
    const CsgExpr::Node& x = e.nodes[n];
    if (x.op == CsgOp::primitive) {
      p.code.push_back({CsgInstr::push, uint8_t(x.primitive)});
      stack.pop_back();
      continue;
    }
    bool a_first = need[x.a] >= need[x.b];
    if (stage < 2) {
      int next = (stage == 0) == a_first ? x.a : x.b;
      ++stage;
      stack.push_back({next, 0});
    } else {
      // With b evaluated first, a lies on top: a − b is then top − below.
      uint8_t code = x.op == CsgOp::union_of       ? CsgInstr::union_of
                     : x.op == CsgOp::intersection ? CsgInstr::intersection
                     : a_first                     ? CsgInstr::difference
                                                   : CsgInstr::reversed_difference;
      p.code.push_back({code, 0});
      stack.pop_back();
    }
  }
  return p;
}

bool evaluate(std::span<const CsgInstr> program, PrimitiveMask present) noexcept {
  uint64_t stack = 0;  // bit 0 is the top
  for (CsgInstr i : program) {
    if (i.code == CsgInstr::push) {
      stack = (stack << 1) | ((present >> (i.primitive & 63)) & 1);
      continue;
    }
    uint64_t t = stack & 1, u = (stack >> 1) & 1, r = 0;
    switch (i.code) {
      case CsgInstr::union_of:
        r = u | t;
        break;
      case CsgInstr::intersection:
        r = u & t;
        break;
      case CsgInstr::difference:
        r = u & ~t;
        break;
      case CsgInstr::reversed_difference:
        r = t & ~u;
        break;
    }
    stack = ((stack >> 2) << 1) | (r & 1);
  }
  return stack & 1;
}

}  // namespace imx
