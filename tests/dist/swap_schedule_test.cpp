#include "dist/swap_schedule.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace imx {
namespace {

TEST(SwapSchedule, ResultsTileTheImageAndPartnersAgree) {
  for (int ranks = 1; ranks <= 12; ++ranks)
    for (size_t pixels : {size_t{1}, size_t{7}, size_t{1000}, size_t{512 * 512}}) {
      std::vector<SwapSchedule> s;
      for (int r = 0; r < ranks; ++r) s.push_back(binary_swap(ranks, r, pixels));
      std::vector<int> covered(pixels, 0);
      for (int r = 0; r < ranks; ++r) {
        for (size_t p = s[r].result.first; p < s[r].result.end; ++p) ++covered[p];
        if (s[r].fold_to >= 0) {
          EXPECT_EQ(s[s[r].fold_to].fold_from, r);
          EXPECT_TRUE(s[r].rounds.empty());
        }
        for (size_t k = 0; k < s[r].rounds.size(); ++k) {
          const SwapRound& mine = s[r].rounds[k];
          const SwapRound& theirs = s[mine.partner].rounds.at(k);
          EXPECT_EQ(theirs.partner, r);
          EXPECT_EQ(mine.keep, theirs.send);
          EXPECT_EQ(mine.send, theirs.keep);
          EXPECT_NE(mine.first, theirs.first);
        }
      }
      for (int c : covered) ASSERT_EQ(c, 1) << ranks << " ranks, " << pixels << " pixels";
    }
}

TEST(SwapSchedule, RoundsAreLogTwoOfTheGroup) {
  EXPECT_EQ(binary_swap(8, 3, 100).rounds.size(), 3u);
  EXPECT_EQ(binary_swap(6, 1, 100).rounds.size(), 2u);
  EXPECT_EQ(binary_swap(6, 5, 100).fold_to, 1);
  EXPECT_EQ(swap_group(1), 1);
  EXPECT_EQ(swap_group(7), 4);
}

}  // namespace
}  // namespace imx
