// The viewer's page (web/) as JavaScript, without a browser: in Node.js, when it is installed,
// index.html's inline script parses and the ES modules of web/js/ link and load (every module
// parses, every import names a module that exists and exports what is imported). Node runs
// main.js with a stand-in `window`, `document` (still loading) and `location`, so nothing of the
// page starts. The browser test (tests/viewer/) runs the page itself.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "temp_dir.hpp"

namespace imx::server {
namespace {

using test::read_bytes;
using test::TempDir;

const std::filesystem::path kWeb = IMX_WEB_DIR;

// Runs a shell command: its exit status, and its output and errors together.
test::CliResult run(const std::string& command) {
  return test::run_shell(command + " 2>&1");
}

bool have_node() {
  return std::system("command -v node > /dev/null 2>&1") == 0;
}

TEST(ViewerPage, InlineScriptParsesInNode) {
  if (!have_node()) GTEST_SKIP() << "node is not installed";
  const std::string html = read_bytes(kWeb / "index.html");
  const size_t open = html.find("<script>");
  ASSERT_NE(open, std::string::npos) << "index.html has no inline classic script";
  const size_t body = open + std::string("<script>").size();
  const size_t close = html.find("</script>", body);
  ASSERT_NE(close, std::string::npos);
  TempDir dir;
  const auto script = dir.write("inline.js", html.substr(body, close - body));
  const test::CliResult r = run("node --check '" + script.string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(ViewerPage, ModulesLinkAndLoadInNode) {
  if (!have_node()) GTEST_SKIP() << "node is not installed";
  TempDir dir;
  int modules = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kWeb / "js")) {
    if (entry.path().extension() != ".js") continue;
    std::filesystem::copy_file(entry.path(), dir.path() / entry.path().filename());
    ++modules;
  }
  ASSERT_GT(modules, 0) << "no module in " << (kWeb / "js");
  dir.write("package.json", R"({"type": "module"})");
  for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
    if (entry.path().extension() == ".js") {
      const test::CliResult r = run("node --check '" + entry.path().string() + "'");
      EXPECT_EQ(r.exit_code, 0) << r.output;
    }
  const auto check = dir.write("check.js", R"(
globalThis.window = globalThis;
globalThis.location = {search: '?token=0', protocol: 'http:', host: 'localhost'};
globalThis.document = {readyState: 'loading', addEventListener() {}};
await import('./main.js');
if (typeof window.viewer !== 'object' || typeof window.viewerStats !== 'object')
  throw new Error('main.js did not publish window.viewer and window.viewerStats');
console.log('loaded');
)");
  const test::CliResult r = run("node '" + check.string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("loaded"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace imx::server
