// Issue 48, item 5: an output never replaces an input. `render in.nii.gz -o in.nii.gz` used to
// write a PNG over its own input, and --save-scene naming an input turned it into JSON. Inputs
// are known by identity (device and inode), so a symbolic or hard link to one is refused too.
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "io/streams/atomic_file.hpp"
#include "io/streams/input_file.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::contains;
using test::read_bytes;
using test::run_cli;

class OutputOverInput : public ::testing::Test {
 protected:
  void SetUp() override {
    const test::CliResult r = run_cli(fmt::format("phantom ct-head --size 32 -o {}", in_.string()));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    original_ = read_bytes(in_);
    ASSERT_FALSE(original_.empty());
  }

  // Runs `args`, which must fail naming `output` as an input of the command, with the input
  // (every name of it) left as it was.
  void expect_refused(const std::string& args, const std::filesystem::path& output) {
    const test::CliResult r = run_cli(args);
    EXPECT_NE(r.exit_code, 0) << args << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, output.string() + ": is an input of this command ("))
        << args << "\n"
        << r.output;
    EXPECT_TRUE(contains(r.output, "); choose another output")) << r.output;
    EXPECT_EQ(read_bytes(in_), original_) << args << ": the input was changed";
    for (const auto& entry : std::filesystem::directory_iterator(dir_.path()))
      EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
  }

  test::TempDir dir_;
  const std::filesystem::path in_ = dir_ / "in.nii.gz";
  std::string original_;
};

TEST_F(OutputOverInput, RenderRefusesToWriteOverItsInput) {
  expect_refused(fmt::format("render {} -o {}", in_.string(), in_.string()), in_);
}

TEST_F(OutputOverInput, ThroughASymbolicLinkToTheInput) {
  const std::filesystem::path link = dir_ / "link.nii.gz";
  std::filesystem::create_symlink(in_.filename(), link);
  expect_refused(fmt::format("render {} -o {}", link.string(), in_.string()), in_);
  expect_refused(fmt::format("render {} -o {}", in_.string(), link.string()), link);
  EXPECT_TRUE(std::filesystem::is_symlink(link));
}

TEST_F(OutputOverInput, ThroughAHardLinkToTheInput) {
  const std::filesystem::path hard = dir_ / "hard.nii.gz";
  std::filesystem::create_hard_link(in_, hard);
  expect_refused(fmt::format("render {} -o {}", in_.string(), hard.string()), hard);
  EXPECT_EQ(read_bytes(hard), original_);
  EXPECT_EQ(std::filesystem::hard_link_count(in_), 2u);
}

TEST_F(OutputOverInput, SaveSceneNamingAnInputIsRefused) {
  const std::filesystem::path png = dir_ / "out.png";
  expect_refused(
      fmt::format("render {} -o {} --save-scene {}", in_.string(), png.string(), in_.string()),
      in_);
}

TEST_F(OutputOverInput, ConvertRefusesToWriteOverItsInput) {
  expect_refused(fmt::format("convert {} -o {}", in_.string(), in_.string()), in_);
  const std::filesystem::path link = dir_ / "same.nii.gz";
  std::filesystem::create_symlink(in_, link);
  expect_refused(fmt::format("convert {} -o {}", link.string(), in_.string()), in_);
}

TEST_F(OutputOverInput, OtherOutputsAreStillWritten) {
  const std::filesystem::path png = dir_ / "out.png", copy = dir_ / "copy.nii.gz";
  EXPECT_EQ(run_cli(fmt::format("render {} -o {}", in_.string(), png.string())).exit_code, 0);
  EXPECT_EQ(run_cli(fmt::format("render {} -o {}", in_.string(), png.string())).exit_code, 0);
  EXPECT_EQ(run_cli(fmt::format("convert {} -o {}", in_.string(), copy.string())).exit_code, 0);
  EXPECT_EQ(run_cli(fmt::format("convert {} -o {}", in_.string(), copy.string())).exit_code, 0);
  EXPECT_EQ(read_bytes(in_), original_);
}

// In one process (the library, the viewer, Python): write_file_atomically refuses any file the
// guarded open has opened as an input, and nothing else.
TEST_F(OutputOverInput, AtomicWriteRefusesAFileOpenedAsAnInput) {
  const std::filesystem::path other = dir_ / "other.txt";
  test::write_bytes(other, "keep");
  open_input(other);
  test::expect_error(
      [&] { write_file_atomically(other, [](std::ostream& o) { o << "replaced"; }); },
      {other.string() + ": is an input of this command (" + other.string() +
       "); choose another output"});
  EXPECT_EQ(read_bytes(other), "keep");
  const std::filesystem::path fresh = dir_ / "fresh.txt";
  write_file_atomically(fresh, [](std::ostream& o) { o << "new"; });
  write_file_atomically(fresh, [](std::ostream& o) { o << "newer"; });  // not an input
  EXPECT_EQ(read_bytes(fresh), "newer");
}

}  // namespace
}  // namespace imx
