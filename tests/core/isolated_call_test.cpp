// run_isolated: a decoder's crash, hang or exception ends its child process, not the caller.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/isolated_call.hpp"
#include "core/library_output.hpp"
#include "intermix/error.hpp"

namespace imx::detail {
namespace {

TEST(IsolatedCall, WhatTheChildWritesComesBackAndItsStderrIsCaptured) {
  std::string seen;
  const IsolatedResult r = run_isolated(
      1 << 20,
      [](std::span<std::byte> out) {
        std::fprintf(stderr, "Corrupt JPEG data: 2 extraneous bytes\n");
        std::memset(out.data(), 7, out.size());
      },
      10.0,
      [&](std::span<const std::byte> out) {
        seen.assign(out.size(), '\0');
        std::memcpy(seen.data(), out.data(), out.size());
      });
  EXPECT_EQ(r.end, IsolatedResult::End::finished);
  ASSERT_EQ(seen.size(), size_t{1} << 20);
  EXPECT_EQ(seen.front(), 7);
  EXPECT_EQ(seen.back(), 7);
  EXPECT_EQ(r.output, "Corrupt JPEG data: 2 extraneous bytes\n");
}

TEST(IsolatedCall, AnExceptionIsAFailureWithItsMessage) {
  bool called = false;
  const IsolatedResult r = run_isolated(
      16, [](std::span<std::byte>) { throw Error("x.dcm: cannot decode"); }, 10.0,
      [&](std::span<const std::byte>) { called = true; });
  EXPECT_EQ(r.end, IsolatedResult::End::failed);
  EXPECT_EQ(r.error, "x.dcm: cannot decode");
  EXPECT_FALSE(called);
}

// A child bounded to 64 MiB more than it had cannot take 1 GiB (a hostile stream's allocation):
// it ends as over_memory; the same work with room finishes.
TEST(IsolatedCall, AChildPastItsMemoryLimitEndsOverMemory) {
#ifdef IMX_SANITIZED
  GTEST_SKIP() << "a sanitizer's allocator reserves address space of its own";
#endif
  auto take = [](size_t bytes) {
    return [bytes](std::span<std::byte> out) {
      std::vector<char> block(bytes, 1);  // touched: really taken
      out[0] = static_cast<std::byte>(block[bytes - 1]);
    };
  };
  const IsolatedResult bounded = run_isolated(
      16, take(size_t{1} << 30), 30.0, [](std::span<const std::byte>) {}, uint64_t{64} << 20);
  EXPECT_EQ(bounded.end, IsolatedResult::End::over_memory);
  const IsolatedResult room = run_isolated(
      16, take(size_t{16} << 20), 30.0, [](std::span<const std::byte>) {}, uint64_t{256} << 20);
  EXPECT_EQ(room.end, IsolatedResult::End::finished);
}

TEST(IsolatedCall, AnAbortOrAFaultEndsOnlyTheChild) {
  const IsolatedResult aborted = run_isolated(
      16, [](std::span<std::byte>) { std::abort(); }, 10.0, [](std::span<const std::byte>) {});
  EXPECT_EQ(aborted.end, IsolatedResult::End::crashed);
  EXPECT_NE(aborted.detail.find("signal 6"), std::string::npos) << aborted.detail;
  const IsolatedResult exited = run_isolated(
      16, [](std::span<std::byte>) { _exit(3); }, 10.0, [](std::span<const std::byte>) {});
  EXPECT_EQ(exited.end, IsolatedResult::End::crashed);
  EXPECT_EQ(exited.detail, "exit status 3");
}

TEST(IsolatedCall, AChildThatHangsIsKilledAtTheTimeout) {
  const IsolatedResult r = run_isolated(
      16, [](std::span<std::byte>) { pause(); }, 0.3, [](std::span<const std::byte>) {});
  EXPECT_EQ(r.end, IsolatedResult::End::timed_out);
}

TEST(LibraryOutput, KeepsLinesNamedBySourceAndTakesThemOnce) {
  take_library_output();
  keep_library_output("decoder", "a.dcm", "first line\n\nsecond line\r\n");
  const std::vector<std::string> lines = take_library_output();
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "decoder (a.dcm): first line");
  EXPECT_EQ(lines[1], "decoder (a.dcm): second line");
  EXPECT_TRUE(take_library_output().empty());
  for (int i = 0; i < 500; ++i) keep_library_output("x", "y", "line");
  EXPECT_EQ(take_library_output().size(), 200u);
}

}  // namespace
}  // namespace imx::detail
