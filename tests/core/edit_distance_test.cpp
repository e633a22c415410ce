#include "core/edit_distance.hpp"

#include <gtest/gtest.h>

namespace imx {
namespace {

TEST(EditDistance, CountsEditsAndSwaps) {
  EXPECT_EQ(edit_distance("", ""), 0u);
  EXPECT_EQ(edit_distance("abc", ""), 3u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("opacity", "opacty"), 1u);
  EXPECT_EQ(edit_distance("matreial", "material"), 1u);  // neighbours swapped
}

TEST(ClosestMatch, SuggestsCloseOrCaseInsensitiveKeys) {
  std::vector<std::string> keys = {"name", "type", "source", "material", "thickness"};
  EXPECT_EQ(closest_match("materal", keys), "material");
  EXPECT_EQ(closest_match("Source", keys), "source");
  EXPECT_EQ(closest_match("THICKNESS", keys), "thickness");
  EXPECT_EQ(closest_match("colour", keys), std::nullopt);
  EXPECT_EQ(closest_match("x", keys), std::nullopt);  // too short to be a misspelling
  EXPECT_EQ(did_you_mean("nme", keys), " (did you mean 'name'?)");
  EXPECT_EQ(did_you_mean("zzzzzz", keys), "");
}

}  // namespace
}  // namespace imx
