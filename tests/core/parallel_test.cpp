// resolve_thread_count: 0 means every core, and a count TBB's arena cannot take is an error.
#include "core/parallel.hpp"

#include <gtest/gtest.h>

#include "intermix/error.hpp"

namespace imx {
namespace {

TEST(Parallel, ThreadCountsAreResolvedOrRefused) {
  EXPECT_GE(resolve_thread_count(0), 1);
  EXPECT_EQ(resolve_thread_count(3), 3);
  EXPECT_EQ(resolve_thread_count(kMaxThreads), kMaxThreads);
  EXPECT_THROW(resolve_thread_count(kMaxThreads + 1), Error);
  EXPECT_THROW(resolve_thread_count(2147483647), Error);
}

}  // namespace
}  // namespace imx
