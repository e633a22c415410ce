// docs/architecture.md's "Longer than the rules" table against the tree: every source file over
// 500 lines is listed there with its current length, and every file listed is still over 500.
// And no SIMD intrinsics outside Highway.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;

const fs::path kRoot = fs::path(IMX_EXAMPLES_DIR).parent_path();
constexpr long kMaxLines = 500;

long line_count(const fs::path& file) {
  const std::string text = test::read_bytes(file);
  return static_cast<long>(std::count(text.begin(), text.end(), '\n'));
}

// The table's rows that name one file: path -> lines.
std::map<std::string, long> listed_files() {
  std::istringstream doc(test::read_bytes(kRoot / "docs/architecture.md"));
  const std::regex row(R"(^\| `([^`]+\.(cpp|hpp|h))` \| (\d+) \|)");
  std::map<std::string, long> out;
  bool in_section = false;
  for (std::string line; std::getline(doc, line);) {
    if (line.starts_with("### ")) in_section = line == "### Longer than the rules";
    std::smatch m;
    if (in_section && std::regex_search(line, m, row)) out[m[1]] = std::stol(m[3]);
  }
  return out;
}

TEST(SourceRules, EveryFileOverFiveHundredLinesIsExplainedWithItsLength) {
  const std::map<std::string, long> listed = listed_files();
  ASSERT_FALSE(listed.empty()) << "no table rows found in docs/architecture.md";
  for (const char* folder : {"src", "apps", "python/src"})
    for (const auto& entry : fs::recursive_directory_iterator(kRoot / folder)) {
      const std::string ext = entry.path().extension().string();
      if (!entry.is_regular_file() || (ext != ".cpp" && ext != ".hpp" && ext != ".h")) continue;
      const long lines = line_count(entry.path());
      if (lines <= kMaxLines) continue;
      const std::string path = fs::relative(entry.path(), kRoot).string();
      const auto it = listed.find(path);
      if (it == listed.end())
        ADD_FAILURE() << path << " has " << lines
                      << " lines: split it, or add a row to docs/architecture.md's "
                         "\"Longer than the rules\" saying why it stays whole";
      else
        EXPECT_EQ(it->second, lines) << path << ": docs/architecture.md says " << it->second;
    }
  for (const auto& [path, lines] : listed)
    EXPECT_GT(line_count(kRoot / path), kMaxLines)
        << path << " is listed in docs/architecture.md but no longer over " << kMaxLines;
}

// One lane kernel source (issue 49): no SIMD intrinsics or their headers anywhere in the
// project's code; vector code goes through Highway, compiled and dispatched per target.
TEST(SourceRules, NoSimdIntrinsicsOutsideThePortableLayer) {
  const std::regex intrinsic(R"(#\s*include\s*<\w*intrin\.h>|\b_mm(256|512)?_[a-z0-9_]+\s*\()");
  int files = 0;
  for (const char* folder : {"src", "include", "apps", "python/src", "tests", "bench", "fuzz"})
    for (const auto& entry : fs::recursive_directory_iterator(kRoot / folder)) {
      const std::string ext = entry.path().extension().string();
      if (!entry.is_regular_file() || (ext != ".cpp" && ext != ".hpp" && ext != ".h")) continue;
      ++files;
      const std::string text = test::read_bytes(entry.path());
      std::smatch m;
      if (std::regex_search(text, m, intrinsic))
        ADD_FAILURE() << fs::relative(entry.path(), kRoot).string() << " uses " << m.str();
    }
  EXPECT_GT(files, 500);  // the walk saw the tree
}

// docs/architecture.md's library table against CMakeLists.txt: every imx_module() has its row,
// naming its folder, and every row's library is still a module.
TEST(SourceRules, EveryModuleHasItsRowInTheLibraryTable) {
  const std::string cmake = test::read_bytes(kRoot / "CMakeLists.txt");
  const std::regex module(R"(\nimx_module\((imx_\w+) (\S+))");
  std::map<std::string, std::string> modules;  // library -> folder under src/
  for (auto it = std::sregex_iterator(cmake.begin(), cmake.end(), module);
       it != std::sregex_iterator(); ++it)
    modules[(*it)[1]] = (*it)[2];
  ASSERT_GT(modules.size(), 10u);
  std::istringstream doc(test::read_bytes(kRoot / "docs/architecture.md"));
  const std::regex row(R"(^\| `(imx_\w+)` \| ([^|]+) \|)");
  std::map<std::string, std::string> rows;
  for (std::string line; std::getline(doc, line);) {
    std::smatch m;
    if (std::regex_search(line, m, row)) rows[m[1]] = m[2];
  }
  for (const auto& [library, folder] : modules) {
    const auto it = rows.find(library);
    if (it == rows.end()) {
      ADD_FAILURE() << library << " (src/" << folder
                    << ") has no row in docs/architecture.md's library table";
      continue;
    }
    EXPECT_NE(it->second.find("`src/" + folder + "`"), std::string::npos)
        << library << "'s row does not name its folder src/" << folder;
  }
  for (const auto& [library, folder] : rows) {
    if (library != "imx_io") {  // the INTERFACE library of every io layer
      EXPECT_TRUE(modules.count(library)) << library << " has a row but is no imx_module";
    }
  }
}

}  // namespace
}  // namespace imx
