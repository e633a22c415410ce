// The bench command end to end: variants time as their own labelled rows in one run.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "scene_fixture.hpp"
#include "temp_dir.hpp"

namespace imx::test {
namespace {

const std::string kTiny = " --width 32 --height 32 --frames 1 --spp 1 --method reference ";

std::string scene_file() {
  return example_scene("shells");
}

TEST(CliBench, TwoVariantsGiveTwoLabelledJsonRows) {
  CliResult r = run_lab("bench " + scene_file() + kTiny +
                        "--variant \"dark:image.background=[0,0,0],render.ert_threshold=1\" "
                        "--variant \"plain:\" --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  nlohmann::json j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  ASSERT_EQ(j["methods"].size(), 2u) << r.output;
  EXPECT_EQ(j["width"], 32);
  EXPECT_EQ(j["methods"][0]["variant"], "dark");
  EXPECT_EQ(j["methods"][0]["label"], "reference/dark");
  EXPECT_EQ(j["methods"][1]["variant"], "plain");
  EXPECT_EQ(j["methods"][1]["method"], "reference");
  EXPECT_DOUBLE_EQ(j["methods"][0]["ratio"].get<double>(), 1.0);
  for (const auto& row : j["methods"]) EXPECT_GT(row["ms_median"].get<double>(), 0.0);
}

TEST(CliBench, TheTablePrintsEveryLabel) {
  CliResult r = run_lab("bench " + scene_file() + kTiny + "--variant a: --variant b:");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("reference/a"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("reference/b"), std::string::npos) << r.output;
}

TEST(CliBench, BadVariantsAreClearErrors) {
  CliResult no_label = run_lab("bench " + scene_file() + kTiny + "--variant image.width=8");
  EXPECT_NE(no_label.exit_code, 0);
  EXPECT_NE(no_label.output.find("LABEL:key=value"), std::string::npos) << no_label.output;
  CliResult twice = run_lab("bench " + scene_file() + kTiny + "--variant a: --variant a:");
  EXPECT_NE(twice.exit_code, 0);
  EXPECT_NE(twice.output.find("twice"), std::string::npos) << twice.output;
  CliResult bad_key =
      run_lab("bench " + scene_file() + kTiny + "--variant \"x:render.no_such_key=1\"");
  EXPECT_NE(bad_key.exit_code, 0);
  EXPECT_NE(bad_key.output.find("no_such_key"), std::string::npos) << bad_key.output;
}

TEST(CliPhantom, WritesAMetaImageThatInfoDescribesAndRejectsOtherExtensions) {
  TempDir dir;
  auto file = (dir / "cube.mha").string();
  CliResult w = run_cli("phantom cube --size 16 -o " + file);
  ASSERT_EQ(w.exit_code, 0) << w.output;
  CliResult i = run_cli("info --json " + file);
  ASSERT_EQ(i.exit_code, 0) << i.output;
  EXPECT_NE(i.output.find("\"dims\":[16,"), std::string::npos) << i.output;
  CliResult bad = run_cli("phantom cube --size 16 -o " + (dir / "cube.vti").string());
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find(".vti"), std::string::npos) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "cube.vti"));
}

}  // namespace
}  // namespace imx::test
