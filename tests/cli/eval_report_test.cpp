// The eval command end to end: its JSON parses and agrees with `compare`, its HTML references
// every image it wrote, and a headless Chromium (when installed) finds the tables.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <regex>
#include <set>

#include "cli_runner.hpp"
#include "scene_fixture.hpp"
#include "temp_dir.hpp"

namespace imx::test {
namespace {

namespace fs = std::filesystem;

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// One small run shared by the tests: a two-object scene (band PSNR) and a CSG scene (most
// methods refuse it), at 40 pixels, 4-spp reference, one timed frame.
class CliEval : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // ctest runs each test in its own process, in parallel: TempDir is one folder per process.
    dir_ = new TempDir;
    result_ = new CliResult(
        run_lab("eval " + example_scene("two-volumes") + " " + example_scene("csg-smile") +
                " --size 40 --ref-spp 4 --frames 1 --out " + (*dir_ / "report").string() +
                " --markdown " + (*dir_ / "eval.md").string()));
  }
  static void TearDownTestSuite() {
    delete result_;
    delete dir_;
  }
  static nlohmann::json report() {
    return nlohmann::json::parse(read_bytes(*dir_ / "report" / "eval.json"));
  }
  static TempDir* dir_;
  static CliResult* result_;
};
TempDir* CliEval::dir_ = nullptr;
CliResult* CliEval::result_ = nullptr;

TEST_F(CliEval, JsonHoldsEveryMethodOnEveryScene) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  nlohmann::json j = report();
  ASSERT_EQ(j["scenes"].size(), 2u);
  EXPECT_GT(j["seconds"].get<double>(), 0.0);
  // The exact command line, global options included.
  EXPECT_EQ(j["command"].get<std::string>().rfind("intermix --quiet eval ", 0), 0u) << j["command"];
  EXPECT_NE(j["command"].get<std::string>().find("--size 40"), std::string::npos);
  const auto& volumes = j["scenes"][0];
  const auto& csg = j["scenes"][1];
  EXPECT_EQ(volumes["name"], "two-volumes");
  EXPECT_EQ(volumes["width"], 40);
  EXPECT_EQ(volumes["reference"]["spp"], 4);
  ASSERT_EQ(volumes["methods"].size(), csg["methods"].size());
  ASSERT_GE(volumes["methods"].size(), 10u);
  // Two objects: the band is theirs and has pixels; every method renders the scene.
  EXPECT_EQ(volumes["band"]["objects"], nlohmann::json({"cube", "ellipsoid"}));
  EXPECT_GT(volumes["band"]["pixels"].get<long>(), 0);
  for (const auto& m : volumes["methods"]) {
    ASSERT_EQ(m["status"], "ok") << m.dump();
    EXPECT_GT(m["ms_median"].get<double>(), 0.0) << m["method"];
    EXPECT_GT(m["ssim"].get<double>(), 0.5) << m["method"];
    EXPECT_FALSE(m["band_psnr_db"].is_null()) << m["method"];
  }
  // CSG: csg renders it; a method that does not is n/a with the reason, not a failure.
  EXPECT_TRUE(csg["band"].is_null());
  int na = 0;
  for (const auto& m : csg["methods"]) {
    if (m["method"] == "csg") {
      EXPECT_EQ(m["status"], "ok");
    }
    if (m["method"] == "mdvr") {
      EXPECT_EQ(m["status"], "n/a");
      EXPECT_NE(m["error"].get<std::string>().find("CSG"), std::string::npos) << m.dump();
    }
    na += m["status"] == "n/a";
  }
  EXPECT_GT(na, 0);
  // The summary counts the n/a rows.
  for (const auto& s : j["summary"])
    if (s["method"] == "mdvr") {
      EXPECT_EQ(s["scenes"], 1);
      EXPECT_EQ(s["not_applicable"], 1);
    }
}

TEST_F(CliEval, PsnrAgreesWithCompareOnTheWrittenImages) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  nlohmann::json j = report();
  const fs::path root = *dir_ / "report";
  for (const auto& scene : j["scenes"])
    for (const auto& m : scene["methods"]) {
      if (m["status"] != "ok" || !m["psnr_db"].is_number()) continue;
      CliResult c = run_cli("compare " + (root / scene["reference"]["image"]).string() + " " +
                            (root / m["image"]).string() + " --json");
      ASSERT_EQ(c.exit_code, 0) << c.output;
      nlohmann::json cj = nlohmann::json::parse(c.output);
      if (!cj["psnr_db"].is_number()) continue;  // equal after 8-bit rounding
      // The PNGs are rounded to 8 bits; the report measured the float images.
      EXPECT_NEAR(cj["psnr_db"].get<double>(), m["psnr_db"].get<double>(), 1.5)
          << scene["name"] << " " << m["method"];
    }
}

TEST_F(CliEval, HtmlReferencesEveryImageAndEveryImageExists) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  const fs::path root = *dir_ / "report";
  std::string html = read_bytes(root / "index.html");
  std::set<std::string> sources;
  std::regex img("<img src=\"([^\"]+)\"");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), img); it != std::sregex_iterator();
       ++it)
    sources.insert((*it)[1]);
  ASSERT_FALSE(sources.empty());
  for (const std::string& src : sources) {
    EXPECT_FALSE(fs::path(src).is_absolute()) << src;
    EXPECT_TRUE(fs::is_regular_file(root / src)) << src;
  }
  nlohmann::json j = report();
  for (const auto& scene : j["scenes"]) {
    EXPECT_TRUE(sources.count(scene["reference"]["image"])) << scene["name"];
    for (const auto& m : scene["methods"])
      if (m["status"] == "ok") {
        EXPECT_TRUE(sources.count(m["image"])) << m["image"];
        EXPECT_TRUE(sources.count(m["heat_map"])) << m["heat_map"];
      }
  }
  EXPECT_EQ(count(html, "<table class=\"scene\">"), 2u);
  EXPECT_EQ(count(html, "<table class=\"summary\">"), 1u);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  // The Markdown tables name the command that made them.
  std::string md = read_bytes(*dir_ / "eval.md");
  EXPECT_NE(md.find("`intermix --quiet eval "), std::string::npos);
  EXPECT_NE(md.find("## two-volumes"), std::string::npos);
}

TEST_F(CliEval, ChromiumLoadsTheReportWithItsTables) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  if (std::system("command -v chromium >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "chromium is not installed (scripts/install-deps installs it)";
  const fs::path index = fs::absolute(*dir_ / "report" / "index.html");
  // Its stdout only: Chromium's stderr is noise.
  const std::string dom =
      run_shell("timeout 90 chromium --headless --no-sandbox --disable-gpu --dump-dom 'file://" +
                index.string() + "' 2>/dev/null")
          .output;
  ASSERT_NE(dom.find("</html>"), std::string::npos) << dom.substr(0, 2000);
  EXPECT_EQ(count(dom, "class=\"scene\""), 2u);
  EXPECT_EQ(count(dom, "class=\"summary\""), 1u);
  EXPECT_NE(dom.find("id=\"scene-two-volumes\""), std::string::npos);
  EXPECT_NE(dom.find("id=\"scene-csg-smile\""), std::string::npos);
}

TEST(CliEvalErrors, ABadSceneFailsBeforeAnythingIsWritten) {
  TempDir dir;
  dir.write("bad.json", R"({"objects": [], "camera": {"eye": [0, 0]}})");
  CliResult r = run_lab("eval " + example_scene("two-volumes") + " " + (dir / "bad.json").string() +
                        " --size 16 --frames 1 --out " + (dir / "report").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("bad.json"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "report" / "index.html"));
  EXPECT_FALSE(fs::exists(dir / "report" / "eval.json"));
  CliResult method = run_lab("eval " + example_scene("two-volumes") + " --method nope --out " +
                             (dir / "report").string());
  EXPECT_NE(method.exit_code, 0);
  EXPECT_NE(method.output.find("'nope'"), std::string::npos) << method.output;
  CliResult band = run_lab("eval " + example_scene("two-volumes") + " --band cube --out " +
                           (dir / "report").string());
  EXPECT_NE(band.exit_code, 0);
  EXPECT_NE(band.output.find("--band 'cube'"), std::string::npos) << band.output;
}

}  // namespace
}  // namespace imx::test
