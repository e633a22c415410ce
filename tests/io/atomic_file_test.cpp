#include <gtest/gtest.h>

#include <csignal>
#include <thread>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include "expect_error.hpp"
#include "io/streams/atomic_file.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::TempDir;

TEST(AtomicFile, WritesTheContentAndLeavesNoTemporary) {
  TempDir dir;
  write_file_atomically(dir / "a.txt", [](std::ostream& out) { out << "hello"; });
  EXPECT_EQ(test::read_bytes(dir / "a.txt"), "hello");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"a.txt"});
}

TEST(AtomicFile, ReplacesAnExistingFile) {
  TempDir dir;
  test::write_bytes(dir / "a.txt", "old content");
  write_file_atomically(dir / "a.txt", [](std::ostream& out) { out << "new"; });
  EXPECT_EQ(test::read_bytes(dir / "a.txt"), "new");
  EXPECT_EQ(dir.entries().size(), 1u);
}

TEST(AtomicFile, AFailingWriterKeepsTheOldFileAndRemovesTheTemporary) {
  TempDir dir;
  test::write_bytes(dir / "a.txt", "old content");
  test::expect_error(
      [&] {
        write_file_atomically(dir / "a.txt", [](std::ostream& out) {
          out << "partial";
          throw Error("a.txt: writer gave up");
        });
      },
      {"writer gave up"});
  EXPECT_EQ(test::read_bytes(dir / "a.txt"), "old content");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"a.txt"});
}

TEST(AtomicFile, AMissingFolderThrowsNamingTheFile) {
  TempDir dir;
  test::expect_error(
      [&] { write_file_atomically(dir / "missing" / "a.txt", [](std::ostream&) {}); },
      {"a.txt", "missing"});
  EXPECT_TRUE(dir.entries().empty());
}

TEST(AtomicFile, RenameOntoAFolderFailsCleanly) {
  TempDir dir;
  std::filesystem::create_directories(dir / "taken" / "child");
  test::expect_error(
      [&] { write_file_atomically(dir / "taken", [](std::ostream& out) { out << "x"; }); },
      {"taken", "is a directory", "only regular files are written"});
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"taken"});
}

// Forks a child whose `writers` threads each start write_file_atomically(dir/"out<i>.txt") with
// a writer that writes part of the output and then blocks for good, so its temporary stays
// alive. Returns the child's pid once every temporary exists.
pid_t fork_blocked_writers(const TempDir& dir, int writers) {
  int ready[2];
  if (::pipe(ready) != 0) ADD_FAILURE() << "pipe failed";
  pid_t pid = ::fork();
  if (pid == 0) {
    ::close(ready[0]);
    std::vector<std::thread> threads;
    for (int i = 0; i < writers; ++i)
      threads.emplace_back([&dir, &ready, i] {
        write_file_atomically(dir / ("out" + std::to_string(i) + ".txt"), [&](std::ostream& out) {
          out << "partial";
          out.flush();
          char c = 'r';
          if (::write(ready[1], &c, 1) != 1) ::_exit(3);
          for (;;) ::pause();
        });
      });
    for (auto& t : threads) t.join();
    ::_exit(2);  // never reached: the writers block until the signal ends the process
  }
  ::close(ready[1]);
  for (int i = 0; i < writers; ++i) {
    char c = 0;
    if (::read(ready[0], &c, 1) != 1) ADD_FAILURE() << "the child died before it was ready";
  }
  ::close(ready[0]);
  return pid;
}

int count_temporaries(const TempDir& dir) {
  int n = 0;
  for (const auto& name : dir.entries()) n += name.find(".tmp-") != std::string::npos;
  return n;
}

// The child must die of `sig` (the handler re-raises it with the default disposition).
void expect_killed_by(pid_t pid, int sig) {
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "exit status " << status;
  EXPECT_EQ(WTERMSIG(status), sig);
}

TEST(AtomicFile, SigtermWhileWritingRemovesTheTemporaryAndKeepsTheOldFile) {
  TempDir dir;
  test::write_bytes(dir / "out0.txt", "old content");
  pid_t pid = fork_blocked_writers(dir, 1);
  ASSERT_GT(pid, 0);
  EXPECT_EQ(count_temporaries(dir), 1);  // the child is inside its writer
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  expect_killed_by(pid, SIGTERM);
  EXPECT_EQ(count_temporaries(dir), 0);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out0.txt"});
  EXPECT_EQ(test::read_bytes(dir / "out0.txt"), "old content");
}

TEST(AtomicFile, SigintWhileWritingANewFileLeavesNothing) {
  TempDir dir;
  pid_t pid = fork_blocked_writers(dir, 1);
  ASSERT_GT(pid, 0);
  EXPECT_EQ(count_temporaries(dir), 1);
  ASSERT_EQ(::kill(pid, SIGINT), 0);
  expect_killed_by(pid, SIGINT);
  EXPECT_TRUE(dir.entries().empty());
}

TEST(AtomicFile, ASignalRemovesTheTemporariesOfEveryThread) {
  TempDir dir;
  pid_t pid = fork_blocked_writers(dir, 4);
  ASSERT_GT(pid, 0);
  EXPECT_EQ(count_temporaries(dir), 4);
  ASSERT_EQ(::kill(pid, SIGTERM), 0);  // delivered to any one of the child's threads
  expect_killed_by(pid, SIGTERM);
  EXPECT_TRUE(dir.entries().empty());
}

TEST(AtomicFile, FinishedWritesAreNotTouchedByALaterSignal) {
  TempDir dir;
  write_file_atomically(dir / "done.txt", [](std::ostream& out) { out << "complete"; });
  test::write_bytes(dir / "out0.txt", "old content");
  pid_t pid = fork_blocked_writers(dir, 1);
  ASSERT_GT(pid, 0);
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  expect_killed_by(pid, SIGTERM);
  EXPECT_EQ(test::read_bytes(dir / "done.txt"), "complete");
  EXPECT_EQ(test::read_bytes(dir / "out0.txt"), "old content");
  EXPECT_EQ(dir.entries().size(), 2u);
}

}  // namespace
}  // namespace imx
