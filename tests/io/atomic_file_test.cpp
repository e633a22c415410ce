#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "io/atomic_file.hpp"
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

}  // namespace
}  // namespace imx
