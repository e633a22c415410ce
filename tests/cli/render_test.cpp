// The render command end to end: determinism across thread counts and the phantom/info tools.
#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "scene_fixture.hpp"
#include "temp_dir.hpp"

namespace imx::test {
namespace {

TEST(CliRender, OneAndTwoThreadsGiveByteIdenticalPngs) {
  TempDir dir;
  const std::string scene = example_scene("ct-implant");
  std::string common = " --width 64 --height 64 --spp 4 --set objects.ct.source.size=64 ";
  CliResult one =
      run_cli("render " + scene + common + "--threads 1 -o " + (dir / "1.png").string());
  ASSERT_EQ(one.exit_code, 0) << one.output;
  CliResult two =
      run_cli("render " + scene + common + "--threads 2 -o " + (dir / "2.png").string());
  ASSERT_EQ(two.exit_code, 0) << two.output;
  std::string a = read_bytes(dir / "1.png"), b = read_bytes(dir / "2.png");
  EXPECT_GT(a.size(), 100u);
  EXPECT_EQ(a, b);
}

TEST(CliRender, PrintsItsTime) {
  TempDir dir;
  // Without --quiet the timing line is printed.
  CliResult r =
      run_shell(std::string(IMX_CLI_PATH) + " render " + example_scene("shells") +
                " --width 32 --height 32 --spp 1 -o " + (dir / "s.png").string() + " 2>&1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(" s -> "), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "s.png"));
}

TEST(CliPhantom, WritesANrrdThatInfoDescribes) {
  TempDir dir;
  auto file = (dir / "cube.nrrd").string();
  CliResult w = run_cli("phantom cube --size 32 -o " + file);
  ASSERT_EQ(w.exit_code, 0) << w.output;
  CliResult i = run_cli("info --json " + file);
  ASSERT_EQ(i.exit_code, 0) << i.output;
  EXPECT_NE(i.output.find("\"dims\":[32,"), std::string::npos) << i.output;
  CliResult bad = run_cli("phantom no-such-thing -o " + (dir / "x.nrrd").string());
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("no-such-thing"), std::string::npos) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.nrrd"));
}

}  // namespace
}  // namespace imx::test
