#include "csg/clip_state.hpp"

#include <gtest/gtest.h>

#include <random>

#include "intermix/error.hpp"

namespace imx {
namespace {

// N7: digits print primitive 0 leftmost and parse back to the same state.
TEST(ClipState, DigitsRoundTrip) {
  EXPECT_EQ(digits(ClipState{0b001, 0b010}, 3), "102");
  EXPECT_EQ(parse_digits("102"), (ClipState{0b001, 0b010}));
  EXPECT_EQ(digits({}, 0), "");
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 1000; ++trial) {
    int n = int(rng() % 65);
    PrimitiveMask ones = rng() & low_primitives(n), zeros = rng() & low_primitives(n) & ~ones;
    ClipState s{ones, zeros};
    std::string text = digits(s, n);
    ASSERT_EQ(text.size(), size_t(n));
    EXPECT_EQ(parse_digits(text), s) << text;
    EXPECT_EQ(digits(parse_digits(text), n), text);
  }
}

// N7: primitive 63 is the last digit and a full 64-bit bit, in ones and in zeros.
TEST(ClipState, Primitive63) {
  PrimitiveMask top = uint64_t{1} << 63;
  ClipState one{top, 0}, zero{0, top};
  EXPECT_EQ(digits(one, 64), std::string(63, '2') + "1");
  EXPECT_EQ(digits(zero, 64), std::string(63, '2') + "0");
  EXPECT_EQ(parse_digits(std::string(63, '2') + "1"), one);
  EXPECT_EQ(parse_digits(std::string(63, '2') + "0"), zero);
  EXPECT_TRUE(matches(one, top));
  EXPECT_FALSE(matches(one, top >> 1));
  EXPECT_FALSE(matches(zero, top));
  EXPECT_TRUE(matches(zero, ~top));
  EXPECT_TRUE(may_accept(one, top, top, ~PrimitiveMask{0}));
  EXPECT_FALSE(may_accept(zero, top, top, ~PrimitiveMask{0}));
  EXPECT_EQ(low_primitives(64), ~PrimitiveMask{0});
  EXPECT_EQ(low_primitives(63), ~top);
}

TEST(ClipState, ParseRejectsBadText) {
  EXPECT_THROW(parse_digits("1a2"), Error);
  EXPECT_THROW(parse_digits("13"), Error);
  EXPECT_NO_THROW(parse_digits(std::string(64, '2')));
  try {
    parse_digits(std::string(65, '1'));
    FAIL() << "65 digits were accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("64"), std::string::npos) << e.what();
  }
}

TEST(ClipState, MatchesAndCovers) {
  ClipState s = parse_digits("102");
  EXPECT_TRUE(matches(s, 0b001));
  EXPECT_TRUE(matches(s, 0b101));
  EXPECT_FALSE(matches(s, 0b011));
  EXPECT_FALSE(matches(s, 0b100));
  EXPECT_TRUE(covers(parse_digits("12"), parse_digits("11")));
  EXPECT_TRUE(covers(parse_digits("12"), parse_digits("10")));
  EXPECT_FALSE(covers(parse_digits("11"), parse_digits("12")));
  EXPECT_FALSE(covers(parse_digits("10"), parse_digits("11")));
}

// N7: may_accept against SPEC §8's definition written per digit, for every state over n <= 5
// primitives, every inside set and every geometric/opacity split.
TEST(ClipState, MayAcceptMatchesDefinition) {
  for (int n = 1; n <= 5; ++n) {
    int states = 1;
    for (int k = 0; k < n; ++k) states *= 3;
    PrimitiveMask used = low_primitives(n);
    for (int code = 0; code < states; ++code) {
      std::string text;
      for (int k = 0, c = code; k < n; ++k, c /= 3) text += char('0' + c % 3);
      ClipState s = parse_digits(text);
      for (PrimitiveMask g = 0; g <= used; ++g)
        for (PrimitiveMask inside = 0; inside <= used; ++inside) {
          bool ones_inside = true, geometric_zero_inside = false, allowed_inside = false;
          for (int k = 0; k < n; ++k) {
            bool in = inside >> k & 1;
            if (text[k] == '1' && !in) ones_inside = false;
            if (text[k] == '0' && in && (g >> k & 1)) geometric_zero_inside = true;
            if (text[k] != '0' && in) allowed_inside = true;
          }
          EXPECT_EQ(may_accept(s, inside, g, used),
                    ones_inside && !geometric_zero_inside && allowed_inside)
              << text << " inside " << inside << " geometric " << g;
        }
    }
  }
}

}  // namespace
}  // namespace imx
