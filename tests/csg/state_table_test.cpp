#include "csg/state_table.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "intermix/error.hpp"
#include "test_trees.hpp"

namespace imx {
namespace {

std::vector<std::string> as_digits(const std::vector<ClipState>& states, int n) {
  std::vector<std::string> out;
  for (ClipState s : states) out.push_back(digits(s, n));
  return out;
}

using Digits = std::vector<std::string>;

// The table of an expression in the test syntax (A = 0, B = 1, C = 2).
Digits table(const char* text, int n, CsgSimplify level = CsgSimplify::merge,
             std::span<const CsgBox> boxes = {}, CsgTableReport* report = nullptr) {
  std::vector<CsgProduct> p = normalize(test::expr(text));
  return as_digits(build_table(p, n, 0, level, boxes, 4096, report).states, n);
}

// Products written as clipping states, for the simplifications that no expression produces.
std::vector<CsgProduct> products(const Digits& states) {
  std::vector<CsgProduct> out;
  for (const std::string& s : states) {
    ClipState c = parse_digits(s);
    out.push_back({c.ones, c.zeros});
  }
  return out;
}

Digits full_of(const Digits& states, int n) {
  return as_digits(build_table(products(states), n, 0, CsgSimplify::full, {}, 4096).states, n);
}

// N3: the seed's examples, primitive 0 leftmost.
TEST(StateTable, SeedExamples) {
  EXPECT_EQ(table("0-1", 2), Digits{"10"});
  EXPECT_EQ(table("0&1", 2), Digits{"11"});
  EXPECT_EQ(table("1-0", 2), Digits{"01"});
  EXPECT_EQ(table("(0-1)|(0&1)", 2, CsgSimplify::none), (Digits{"10", "11"}));
  EXPECT_EQ(table("(0-1)|(0&1)", 2), Digits{"12"});
  EXPECT_EQ(table("(0-1)-(1&2)", 3), Digits{"102"});
  EXPECT_EQ(table("((0&1)&2)&0", 3), Digits{"111"});
  EXPECT_TRUE(table("0-0", 1).empty());
  EXPECT_TRUE(table("0-0", 1, CsgSimplify::full).empty());
  EXPECT_EQ(table("((0&1)-2)|((1&2)-0)", 3), (Digits{"011", "110"}));
}

TEST(StateTable, MergeLevel) {
  EXPECT_EQ(table("0|1", 2), (Digits{"12", "21"}));
  EXPECT_EQ(table("(1-0)|(0&1)|(0-1)", 2), (Digits{"12", "21"}));
  // Duplicates and absorption: 12 + 11 + 12 -> 12.
  EXPECT_EQ(
      as_digits(
          build_table(products({"12", "11", "12"}), 2, 0, CsgSimplify::merge, {}, 4096).states, 2),
      Digits{"12"});
  // The seven minterms of three primitives (the seed's "7 comb. of 222").
  EXPECT_EQ(table("(0-1-2)|(1-0-2)|(2-0-1)|((0&1)-2)|((0&2)-1)|((1&2)-0)|(0&1&2)", 3),
            (Digits{"122", "212", "221"}));
  // none keeps the products as they are, duplicates included.
  EXPECT_EQ(table("(0-1)|(0-1)", 2, CsgSimplify::none), (Digits{"10", "10"}));
}

// N3: consensus with "nothing present" as a don't care reaches the seed's 22 and 202.
TEST(StateTable, FullLevel) {
  EXPECT_EQ(full_of({"12", "21"}, 2), Digits{"22"});
  EXPECT_EQ(full_of({"100", "101", "001", "000"}, 3), Digits{"202"});
  EXPECT_EQ(table("0|1", 2, CsgSimplify::full), Digits{"22"});
  EXPECT_EQ(table("(0|1)|2", 3, CsgSimplify::full), Digits{"222"});
  EXPECT_EQ(table("0-1", 2, CsgSimplify::full), Digits{"20"});  // 10 + the don't care 00
  EXPECT_EQ(table("(0-2)|1", 3, CsgSimplify::full), (Digits{"212", "220"}));
  EXPECT_EQ(table("((0&1)-2)|((1&2)-0)", 3, CsgSimplify::full), (Digits{"011", "110"}));
  // The prime 20 of "A" (12 + 20) is redundant next to 12.
  EXPECT_EQ(full_of({"12"}, 2), Digits{"12"});
}

TEST(StateTable, ReportHasEachStage) {
  CsgTableReport r;
  table("(0-1)|(0&1)|(1-0)", 2, CsgSimplify::full, {}, &r);
  EXPECT_EQ(as_digits(r.products, 2), (Digits{"10", "11", "01"}));
  EXPECT_EQ(as_digits(r.after_merge, 2), (Digits{"12", "21"}));
  EXPECT_EQ(as_digits(r.after_pruning, 2), (Digits{"12", "21"}));
  EXPECT_EQ(as_digits(r.after_full, 2), Digits{"22"});
  EXPECT_TRUE(r.pruned.empty());
  table("0-1", 2, CsgSimplify::none, {}, &r);
  EXPECT_EQ(as_digits(r.products, 2), Digits{"10"});
  EXPECT_TRUE(r.after_merge.empty());
}

CsgBox box(double lo, double hi) {
  return {glm::dvec3(lo), glm::dvec3(hi)};
}

// N6: bounding-box pruning, both rules; touching boxes meet.
TEST(StateTable, BoxPruning) {
  std::vector<CsgBox> disjoint{box(0, 1), box(2, 3)};
  CsgTableReport r;
  EXPECT_TRUE(table("0&1", 2, CsgSimplify::merge, disjoint, &r).empty());
  EXPECT_EQ(r.pruned, Digits{"dropped 11: boxes of 0 and 1 do not meet"});
  EXPECT_EQ(table("0-1", 2, CsgSimplify::merge, disjoint, &r), Digits{"12"});
  EXPECT_EQ(r.pruned, Digits{"digit 0 of 1 -> 2 in 10"});
  EXPECT_EQ(as_digits(r.after_merge, 2), Digits{"10"});
  // A − B, A ∩ B -> 12 + nothing: still 12, and the none level ignores boxes.
  EXPECT_EQ(table("(0-1)|(0&1)", 2, CsgSimplify::merge, disjoint), Digits{"12"});
  EXPECT_EQ(table("0&1", 2, CsgSimplify::none, disjoint), Digits{"11"});

  std::vector<CsgBox> touching{box(0, 1), box(1, 2)};
  EXPECT_EQ(table("0&1", 2, CsgSimplify::merge, touching), Digits{"11"});
  EXPECT_EQ(table("0-1", 2, CsgSimplify::merge, touching), Digits{"10"});
  // Touching on one axis only, apart on another: apart.
  std::vector<CsgBox> apart_in_y{box(0, 1), {glm::dvec3(1, 2, 0), glm::dvec3(2, 3, 1)}};
  EXPECT_TRUE(table("0&1", 2, CsgSimplify::merge, apart_in_y).empty());

  // C misses the common box of A and B although it meets A.
  std::vector<CsgBox> three{box(0, 4), box(0, 1), box(3, 4)};
  EXPECT_EQ(table("(0&1)-2", 3, CsgSimplify::merge, three, &r), Digits{"112"});
  EXPECT_EQ(table("(0-2)&(1|2)", 3, CsgSimplify::merge, three), (Digits{"112"}));

  std::vector<CsgBox> empty_box{box(0, 1), CsgBox{}};
  EXPECT_TRUE(table("0&1", 2, CsgSimplify::merge, empty_box, &r).empty());
  EXPECT_EQ(r.pruned, Digits{"dropped 11: the box of 1 is empty"});
  EXPECT_EQ(table("0-1", 2, CsgSimplify::full, empty_box), Digits{"12"});
}

TEST(StateTable, LimitsAndBadInput) {
  std::vector<CsgProduct> five = products({"1222", "2122", "2212", "2221", "1111"});
  EXPECT_NO_THROW(build_table(five, 4, 0, CsgSimplify::merge, {}, 5));
  try {
    build_table(five, 4, 0, CsgSimplify::none, {}, 4);
    FAIL() << "5 states accepted with max_states 4";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("5 CSG clipping states"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("render.csg_max_states = 4"), std::string::npos);
  }
  std::vector<CsgBox> one_box{box(0, 1)};
  EXPECT_THROW(build_table(five, 4, 0, CsgSimplify::merge, one_box, 4096), Error);
  EXPECT_THROW(build_table(five, 3, 0, CsgSimplify::merge, {}, 4096), Error);
  EXPECT_THROW(build_table(five, 65, 0, CsgSimplify::merge, {}, 4096), Error);
  EXPECT_TRUE(build_table({}, 0, 0, CsgSimplify::full, {}, 4096).states.empty());
}

TEST(StateTable, ParseSimplify) {
  EXPECT_EQ(parse_csg_simplify("none"), CsgSimplify::none);
  EXPECT_EQ(parse_csg_simplify("merge"), CsgSimplify::merge);
  EXPECT_EQ(parse_csg_simplify("full"), CsgSimplify::full);
  try {
    parse_csg_simplify("fast");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'fast'"), std::string::npos) << e.what();
  }
}

TEST(StateTable, PerRayTests) {
  // A − B with B a region (geometric) primitive or an opacity-presence volume.
  for (PrimitiveMask geometric : {PrimitiveMask{0b10}, PrimitiveMask{0}}) {
    CsgTable t =
        build_table(normalize(test::expr("0-1")), 2, geometric, CsgSimplify::merge, {}, 4096);
    EXPECT_EQ(t.used, 0b11u);
    EXPECT_EQ(t.geometric, geometric);
    EXPECT_TRUE(matches_any(t.states, 0b01));
    EXPECT_FALSE(matches_any(t.states, 0b11));
    EXPECT_FALSE(matches_any(t.states, 0b10));
    EXPECT_TRUE(may_accept_any(t.states, 0b01, t.geometric, t.used));
    EXPECT_FALSE(may_accept_any(t.states, 0b10, t.geometric, t.used));
    EXPECT_FALSE(may_accept_any(t.states, 0, t.geometric, t.used));
    // Inside both: B cuts for sure only when it is present wherever it is inside.
    EXPECT_EQ(may_accept_any(t.states, 0b11, t.geometric, t.used), geometric == 0);
  }
  // 22 has no 1-digit, yet an interval inside nothing must still be skipped.
  CsgTable u = build_table(normalize(test::expr("0|1")), 2, 0b11, CsgSimplify::full, {}, 4096);
  ASSERT_EQ(as_digits(u.states, 2), Digits{"22"});
  EXPECT_FALSE(may_accept_any(u.states, 0, u.geometric, u.used));
  EXPECT_TRUE(may_accept_any(u.states, 0b10, u.geometric, u.used));
}

// The example scenes' expressions (example_states.py): state counts per level, up to 64 primitives.
TEST(StateTable, ExampleScenes) {
  auto count = [](const char* text, int n, CsgSimplify level) {
    return build_table(normalize(test::expr(text)), n, 0, level, {}, 4096).states.size();
  };
  const char* vessels = "(0-5)|(1-6)|((2&3)-4)|(4-5-9-10)|((7|8)-6)";
  EXPECT_EQ(count(vessels, 11, CsgSimplify::none), 6u);
  EXPECT_EQ(count(vessels, 11, CsgSimplify::merge), 6u);
  EXPECT_EQ(count(vessels, 11, CsgSimplify::full), 6u);
  // "first op from op from+1 … op last"
  auto chain = [](std::string text, char op, int from, int last) {
    for (int k = from; k <= last; ++k) {
      text += op;
      text += std::to_string(k);
    }
    return text;
  };
  std::string slices = chain("0&(1", '|', 2, 20) + ")", gaps = chain("0-(1", '|', 2, 19) + ")";
  std::string cylinders = chain("0", '-', 1, 63), volumes = chain("0", '|', 1, 20);
  EXPECT_EQ(count(slices.c_str(), 21, CsgSimplify::merge), 20u);
  EXPECT_EQ(count(slices.c_str(), 21, CsgSimplify::full), 20u);
  EXPECT_EQ(count(gaps.c_str(), 20, CsgSimplify::merge), 1u);
  CsgTable box = build_table(normalize(test::expr(cylinders)), 64, 0, CsgSimplify::full, {}, 4096);
  EXPECT_EQ(as_digits(box.states, 64), Digits{"2" + std::string(63, '0')});
  // 21 volumes (above the truth-table limit of the redundancy check) still reach one state.
  EXPECT_EQ(table(volumes.c_str(), 21, CsgSimplify::full), Digits{std::string(21, '2')});
  EXPECT_EQ(count(volumes.c_str(), 21, CsgSimplify::merge), 21u);
}

}  // namespace
}  // namespace imx
