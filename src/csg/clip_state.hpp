// ClipState: one product of a CSG sum of products as a row of 1/0/2 digits over primitive bits.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx {

using PrimitiveMask = uint64_t;  // bit k = primitive k
inline constexpr int kMaxCsgPrimitives = 64;

// The mask of primitives 0..n-1 (n <= 64; a plain shift by 64 would be undefined).
constexpr PrimitiveMask low_primitives(int n) {
  return n >= kMaxCsgPrimitives ? ~PrimitiveMask{0} : (PrimitiveMask{1} << n) - 1;
}

// Digit 1 for the primitives in `ones`, 0 for those in `zeros`, 2 (don't care) for the rest.
struct ClipState {
  PrimitiveMask ones = 0, zeros = 0;
  friend bool operator==(const ClipState&, const ClipState&) = default;
};

// Every 1-digit primitive is present and every 0-digit one absent.
constexpr bool matches(ClipState s, PrimitiveMask present) {
  return (s.ones & ~present) == 0 && (s.zeros & present) == 0;
}

// Every assignment that matches `inner` also matches `outer` (absorption: 12 covers 11 and 10).
constexpr bool covers(ClipState outer, ClipState inner) {
  return (outer.ones & ~inner.ones) == 0 && (outer.zeros & ~inner.zeros) == 0;
}

// SPEC §8's exact interval test. `inside`: primitives whose region holds the interval;
// `geometric`: those present wherever they are inside; `used`: the expression's primitives.
// A 1-digit must be inside, a geometric 0-digit must not be, and something the state allows to be
// present (digit 1 or 2) must be inside, because nothing present never renders.
constexpr bool may_accept(ClipState s, PrimitiveMask inside, PrimitiveMask geometric,
                          PrimitiveMask used) {
  return (s.ones & ~inside) == 0 && (s.zeros & inside & geometric) == 0 &&
         (~s.zeros & used & inside) != 0;
}

// Some state matches `present`: the per-sample visibility test (inline: it runs per step).
inline bool matches_any(std::span<const ClipState> states, PrimitiveMask present) {
  for (const ClipState& s : states)
    if (matches(s, present)) return true;
  return false;
}

// Some state may accept an interval whose region mask is `inside` (may_accept of each).
inline bool may_accept_any(std::span<const ClipState> states, PrimitiveMask inside,
                           PrimitiveMask geometric, PrimitiveMask used) {
  for (const ClipState& s : states)
    if (may_accept(s, inside, geometric, used)) return true;
  return false;
}

// The state's first n digits, primitive 0 leftmost, e.g. "102".
inline std::string digits(ClipState s, int n) {
  std::string out;
  for (int k = 0; k < n; ++k) {
    PrimitiveMask bit = PrimitiveMask{1} << k;
    out += (s.ones & bit) ? '1' : (s.zeros & bit) ? '0' : '2';
  }
  return out;
}

// The inverse of digits(); throws Error on a character other than 0, 1, 2 or more than 64 digits.
inline ClipState parse_digits(std::string_view text) {
  if (text.size() > size_t(kMaxCsgPrimitives))
    throw Error(fmt::format("clipping state '{}' has {} digits, at most {} are allowed", text,
                            text.size(), kMaxCsgPrimitives));
  ClipState s;
  for (size_t k = 0; k < text.size(); ++k) {
    PrimitiveMask bit = PrimitiveMask{1} << k;
    if (text[k] == '1')
      s.ones |= bit;
    else if (text[k] == '0')
      s.zeros |= bit;
    else if (text[k] != '2')
      throw Error(
          fmt::format("clipping state '{}': digit {} is '{}', not 0, 1 or 2", text, k, text[k]));
  }
  return s;
}

}  // namespace imx
