#include "csg/state_table.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx {
namespace {

int digit(ClipState s, int k) {
  PrimitiveMask bit = PrimitiveMask{1} << k;
  return (s.zeros & bit) ? 0 : (s.ones & bit) ? 1 : 2;
}

// The order of the digit strings (primitive 0 first, 0 < 1 < 2), so tables print sorted.
bool digits_less(ClipState a, ClipState b) {
  PrimitiveMask differ = (a.ones ^ b.ones) | (a.zeros ^ b.zeros);
  if (differ == 0) return false;
  int k = std::countr_zero(differ);
  return digit(a, k) < digit(b, k);
}

void sort_unique(std::vector<ClipState>& s) {
  std::sort(s.begin(), s.end(), digits_less);
  s.erase(std::unique(s.begin(), s.end()), s.end());
}

void check_count(size_t count, int max_states, const char* stage) {
  if (count > size_t(max_states))
    throw Error(fmt::format("{} CSG clipping states {}, more than render.csg_max_states = {}",
                            count, stage, max_states));
}

// Drops every state that another one covers; `s` must be free of duplicates.
void absorb(std::vector<ClipState>& s) {
  std::vector<ClipState> kept;
  for (ClipState a : s)
    if (std::none_of(s.begin(), s.end(), [&](ClipState b) { return b != a && covers(b, a); }))
      kept.push_back(a);
  s = std::move(kept);
}

// Duplicates, absorption and X1Y + X0Y = X2Y to a fixed point. Every merged state is new (it
// would otherwise cover X1Y, which absorption removed), so each round adds states or ends.
std::vector<ClipState> merge(std::vector<ClipState> s, int max_states) {
  sort_unique(s);
  absorb(s);
  for (;;) {
    std::vector<ClipState> merged;
    for (ClipState a : s)
      for (PrimitiveMask ones = a.ones; ones != 0; ones &= ones - 1) {
        PrimitiveMask bit = ones & -ones;
        ClipState partner{a.ones & ~bit, a.zeros | bit};
        if (std::binary_search(s.begin(), s.end(), partner, digits_less))
          merged.push_back({a.ones & ~bit, a.zeros});
      }
    if (merged.empty()) return s;
    s.insert(s.end(), merged.begin(), merged.end());
    sort_unique(s);
    absorb(s);
    check_count(s.size(), max_states, "after merging");
  }
}

bool is_empty(const CsgBox& b) {
  return b.lo.x > b.hi.x || b.lo.y > b.hi.y || b.lo.z > b.hi.z;
}

CsgBox meet(const CsgBox& a, const CsgBox& b) {
  return {glm::max(a.lo, b.lo), glm::min(a.hi, b.hi)};
}

// Why the 1-digit boxes of `s` have no common point. AABBs that meet pairwise meet all together
// (per axis, intervals do), so an empty box or a disjoint pair always explains it.
std::string why_apart(ClipState s, std::span<const CsgBox> boxes) {
  int n = int(boxes.size());
  for (int i = 0; i < n; ++i)
    if ((s.ones >> i & 1) && is_empty(boxes[i])) return fmt::format("the box of {} is empty", i);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if ((s.ones >> i & 1) && (s.ones >> j & 1) && is_empty(meet(boxes[i], boxes[j])))
        return fmt::format("boxes of {} and {} do not meet", i, j);
  return "their boxes do not meet";
}

// Sound where a present primitive lies inside its box: a state whose 1-digits cannot all be
// present at one point never matches, and a 0-digit outside their common box is always absent.
std::vector<ClipState> prune(const std::vector<ClipState>& states, std::span<const CsgBox> boxes,
                             std::vector<std::string>& notes) {
  int n = int(boxes.size());
  std::vector<ClipState> out;
  for (ClipState s : states) {
    if (s.ones == 0) {  // no positive box to test against
      out.push_back(s);
      continue;
    }
    CsgBox common{glm::dvec3(-INFINITY), glm::dvec3(INFINITY)};
    for (int k = 0; k < n; ++k)
      if (s.ones >> k & 1) common = meet(common, boxes[k]);
    if (is_empty(common)) {
      notes.push_back(fmt::format("dropped {}: {}", digits(s, n), why_apart(s, boxes)));
      continue;
    }
    ClipState t = s;
    for (int k = 0; k < n; ++k)
      if ((s.zeros >> k & 1) && is_empty(meet(common, boxes[k]))) {
        t.zeros &= ~(PrimitiveMask{1} << k);
        notes.push_back(fmt::format("digit 0 of {} -> 2 in {}", k, digits(s, n)));
      }
    out.push_back(t);
  }
  return out;
}

// Adds an implicant unless one already covers it, removing those it covers (keeps an antichain).
void insert_implicant(std::vector<ClipState>& s, ClipState c, int max_states) {
  if (std::any_of(s.begin(), s.end(), [&](ClipState x) { return covers(x, c); })) return;
  std::erase_if(s, [&](ClipState x) { return covers(c, x); });
  s.push_back(c);
  check_count(s.size(), max_states, "among the prime implicants");
}

// Tison's method: for each primitive in turn, add every consensus on it, then absorb; what
// remains is every prime implicant. "Nothing present" joins as a don't care, since E(0) = false
// for ∪/∩/− and an empty sample renders nothing either way.
std::vector<ClipState> prime_implicants(std::vector<ClipState> s, int n, int max_states) {
  ClipState nothing{0, low_primitives(n)};
  s.push_back(nothing);
  sort_unique(s);
  absorb(s);
  for (int k = 0; k < n; ++k) {
    PrimitiveMask bit = PrimitiveMask{1} << k;
    std::vector<ClipState> with_1, with_0;
    for (ClipState x : s) {
      if (x.ones & bit) with_1.push_back(x);
      if (x.zeros & bit) with_0.push_back(x);
    }
    for (ClipState p : with_1)
      for (ClipState q : with_0)
        if (((p.ones & q.zeros) | (p.zeros & q.ones)) == bit)
          insert_implicant(s, {(p.ones | q.ones) & ~bit, (p.zeros | q.zeros) & ~bit}, max_states);
  }
  std::erase(s, nothing);  // it covers only the don't care
  return s;
}

// For each state of `cover`, the largest prime containing it (the first in digit order on ties):
// a cover by primes that is never larger than `cover`.
std::vector<ClipState> lift(const std::vector<ClipState>& cover,
                            const std::vector<ClipState>& primes) {
  std::vector<ClipState> out;
  for (ClipState c : cover) {
    const ClipState* best = nullptr;
    for (const ClipState& p : primes)
      if (covers(p, c) &&
          (!best || std::popcount(p.ones | p.zeros) < std::popcount(best->ones | best->zeros)))
        best = &p;
    out.push_back(*best);  // some prime contains every implicant
  }
  sort_unique(out);
  return out;
}

// Removes states whose non-empty assignments the others cover, the most specific first, by
// counting on the truth table (2^n entries).
void drop_redundant(std::vector<ClipState>& s, int n) {
  std::vector<uint32_t> count(size_t{1} << n, 0);
  auto for_each_assignment = [&](ClipState x, auto&& f) {
    PrimitiveMask free = low_primitives(n) & ~(x.ones | x.zeros);
    for (PrimitiveMask sub = free;; sub = (sub - 1) & free) {
      f(x.ones | sub);
      if (sub == 0) break;
    }
  };
  for (ClipState x : s) for_each_assignment(x, [&](PrimitiveMask m) { ++count[m]; });
  std::stable_sort(s.begin(), s.end(), [](ClipState a, ClipState b) {
    return std::popcount(a.ones | a.zeros) > std::popcount(b.ones | b.zeros);
  });
  std::vector<ClipState> kept;
  for (ClipState x : s) {
    bool redundant = true;
    for_each_assignment(x, [&](PrimitiveMask m) { redundant &= m == 0 || count[m] >= 2; });
    if (redundant)
      for_each_assignment(x, [&](PrimitiveMask m) { --count[m]; });
    else
      kept.push_back(x);
  }
  s = std::move(kept);
}

}  // namespace

CsgSimplify parse_csg_simplify(std::string_view text) {
  if (text == "none") return CsgSimplify::none;
  if (text == "merge") return CsgSimplify::merge;
  if (text == "full") return CsgSimplify::full;
  throw Error(fmt::format("csg_simplify is '{}'; expected none, merge or full", text));
}

CsgTable build_table(std::span<const CsgProduct> products, int primitive_count,
                     PrimitiveMask geometric, CsgSimplify level, std::span<const CsgBox> boxes,
                     int max_states, CsgTableReport* report) {
  if (primitive_count < 0 || primitive_count > kMaxCsgPrimitives)
    throw Error(fmt::format("CSG table: {} primitives, at most {} are allowed", primitive_count,
                            kMaxCsgPrimitives));
  if (!boxes.empty() && boxes.size() != size_t(primitive_count))
    throw Error(
        fmt::format("CSG table: {} boxes for {} primitives", boxes.size(), primitive_count));
  CsgTable t;
  t.primitive_count = primitive_count;
  t.used = low_primitives(primitive_count);
  t.geometric = geometric & t.used;
  std::vector<ClipState> states;
  for (CsgProduct p : products) {
    if ((p.pos | p.neg) & ~t.used)
      throw Error(
          fmt::format("CSG table: a product names a primitive beyond the {}", primitive_count));
    if ((p.pos & p.neg) == 0) states.push_back({p.pos, p.neg});
  }
  check_count(states.size(), max_states, "from normalization");
  CsgTableReport scratch;
  CsgTableReport& r = report ? *report : scratch;
  r = {};
  r.products = states;
  if (level != CsgSimplify::none) {
    states = merge(std::move(states), max_states);
    r.after_merge = states;
    if (!boxes.empty()) states = merge(prune(states, boxes, r.pruned), max_states);
    r.after_pruning = states;
  }
  if (level == CsgSimplify::full) {
    states = lift(states, prime_implicants(states, primitive_count, max_states));
    if (primitive_count <= 20) drop_redundant(states, primitive_count);
    std::sort(states.begin(), states.end(), digits_less);
    r.after_full = states;
  }
  t.states = std::move(states);
  return t;
}

}  // namespace imx
