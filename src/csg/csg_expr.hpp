// CsgExpr: a CSG expression over numbered primitives, and its postfix program for per-sample tests.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "csg/clip_state.hpp"
#include "intermix/scene.hpp"

namespace imx {

// A primitive of an expression: the scene object and how its presence is decided.
struct CsgPrimitive {
  ObjectRef object;
  CsgPresence presence;
};

// A tree (each node has at most one parent) in an arena; primitive index = bit.
struct CsgExpr {
  struct Node {
    CsgOp op = CsgOp::primitive;
    int primitive = -1;  // primitive nodes: 0..primitive_count-1
    int a = -1, b = -1;  // operator nodes: the operands
  };
  std::vector<Node> nodes;
  int root = -1;
  int primitive_count = 0;
};

// Numbers the primitives of the scene's expression (filling `primitives`, index = bit) by first
// appearance in a depth-first, left-to-right walk; the same object with the same presence is one
// primitive. Throws Error for more than kMaxCsgPrimitives primitives, an object with two presences,
// an object-less leaf, bad node indices, or a node used twice (which includes cycles).
CsgExpr compile_expression(const CsgExpression& e, std::vector<CsgPrimitive>& primitives);

// Throws Error unless e.root is a tree over primitives 0..primitive_count-1 (<= 64).
void validate(const CsgExpr& e);

// Builders for tests and tools; they return the new node's index.
int add_primitive(CsgExpr& e, int primitive);  // also raises primitive_count to cover it
int add_op(CsgExpr& e, CsgOp op, int a, int b);

// Infix text of the subtree at `node` (-1: the root), e.g. "((0 ∪ 1) − 2)", with primitive numbers
// or, in the second form, names[primitive].
std::string to_string(const CsgExpr& e, int node = -1);
std::string to_string(const CsgExpr& e, std::span<const std::string> names, int node = -1);

// One postfix instruction; `primitive` is read by push only.
struct CsgInstr {
  enum Code : uint8_t { push, union_of, intersection, difference, reversed_difference };
  uint8_t code;
  uint8_t primitive;
};

// Evaluated on a 64-deep bit stack. Binary operators pop the top (t) and the one below (u):
// difference pushes u − t, reversed_difference t − u.
struct CsgProgram {
  std::vector<CsgInstr> code;
  int primitive_count = 0;
};

// Emits the deeper operand first (Sethi–Ullman), so the stack never holds more than
// floor(log2(leaves)) + 1 values; throws Error if that would exceed 64 anyway.
CsgProgram compile_program(const CsgExpr& e);

// E(present): the expression's value where exactly the primitives in `present` are present.
bool evaluate(std::span<const CsgInstr> program, PrimitiveMask present) noexcept;
inline bool evaluate(const CsgProgram& p, PrimitiveMask present) noexcept {
  return evaluate(std::span<const CsgInstr>(p.code), present);
}

}  // namespace imx
