// The viewer's page (web/) as JavaScript, without a browser: in Node.js, when it is installed,
// index.html's inline script parses and the ES modules of web/js/ link and load (every module
// parses, every import names a module that exists and exports what is imported). Node runs
// main.js with a stand-in `window`, `document` (still loading) and `location`, so nothing of the
// page starts. The browser test (tests/viewer/) runs the page itself.
#include <stdlib.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

#include <gtest/gtest.h>

namespace imx::server {
namespace {

const std::filesystem::path kWeb = IMX_WEB_DIR;

// A fresh folder under the system temporary folder for the files node reads, removed afterwards.
class Scratch {
 public:
  Scratch() {
    std::string name = (std::filesystem::temp_directory_path() / "imx-viewer-page-XXXXXX").string();
    if (::mkdtemp(name.data())) path_ = name;
  }
  ~Scratch() {
    std::error_code ec;
    if (!path_.empty()) std::filesystem::remove_all(path_, ec);
  }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name, std::ios::binary) << text;
    return path_ / name;
  }

 private:
  std::filesystem::path path_;
};

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Runs a shell command; its exit status, and its output and errors in `output`.
int run(const std::string& command, std::string& output) {
  output.clear();
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  char buffer[4096];
  for (size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) output.append(buffer, n);
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

bool have_node() {
  return std::system("command -v node > /dev/null 2>&1") == 0;
}

TEST(ViewerPage, InlineScriptParsesInNode) {
  if (!have_node()) GTEST_SKIP() << "node is not installed";
  const std::string html = read_text(kWeb / "index.html");
  const size_t open = html.find("<script>");
  ASSERT_NE(open, std::string::npos) << "index.html has no inline classic script";
  const size_t body = open + std::string("<script>").size();
  const size_t close = html.find("</script>", body);
  ASSERT_NE(close, std::string::npos);
  Scratch dir;
  ASSERT_FALSE(dir.path().empty()) << "no temporary folder";
  const auto script = dir.write("inline.js", html.substr(body, close - body));
  std::string output;
  EXPECT_EQ(run("node --check '" + script.string() + "'", output), 0) << output;
}

TEST(ViewerPage, ModulesLinkAndLoadInNode) {
  if (!have_node()) GTEST_SKIP() << "node is not installed";
  Scratch dir;
  ASSERT_FALSE(dir.path().empty()) << "no temporary folder";
  int modules = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kWeb / "js")) {
    if (entry.path().extension() != ".js") continue;
    std::filesystem::copy_file(entry.path(), dir.path() / entry.path().filename());
    ++modules;
  }
  ASSERT_GT(modules, 0) << "no module in " << (kWeb / "js");
  dir.write("package.json", R"({"type": "module"})");
  std::string output;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
    if (entry.path().extension() == ".js")
      EXPECT_EQ(run("node --check '" + entry.path().string() + "'", output), 0) << output;
  const auto check = dir.write("check.js", R"(
globalThis.window = globalThis;
globalThis.location = {search: '?token=0', protocol: 'http:', host: 'localhost'};
globalThis.document = {readyState: 'loading', addEventListener() {}};
await import('./main.js');
if (typeof window.viewer !== 'object' || typeof window.viewerStats !== 'object')
  throw new Error('main.js did not publish window.viewer and window.viewerStats');
console.log('loaded');
)");
  EXPECT_EQ(run("node '" + check.string() + "'", output), 0) << output;
  EXPECT_NE(output.find("loaded"), std::string::npos) << output;
}

}  // namespace
}  // namespace imx::server
