// TempDir: a fresh folder for one test, under the system temporary folder, removed with it; and
// whole-file reads and writes for the files tests make there.
#pragma once
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>
#include <vector>

#include <gtest/gtest.h>

namespace imx::test {

inline void write_bytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream out(file, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::string read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Named after the running test (or test suite, made in SetUpTestSuite), the process and a count,
// so that tests run in parallel, in one process or several, never share one.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> count{0};
    path_ =
        std::filesystem::temp_directory_path() /
        ("imx-" + test_name() + "-" + std::to_string(::getpid()) + "-" + std::to_string(count++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::filesystem::path& name) const { return path_ / name; }

  // Writes `bytes` to `name` (its folders made as needed) and returns the file's path.
  std::filesystem::path write(const std::filesystem::path& name, const std::string& bytes) const {
    const std::filesystem::path file = path_ / name;
    std::filesystem::create_directories(file.parent_path());
    write_bytes(file, bytes);
    return file;
  }

  // Names of everything in the folder (to check that nothing stray was left behind).
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(path_))
      names.push_back(e.path().filename().string());
    return names;
  }

 private:
  // "Suite.Test" of the running test, its characters safe in a file name.
  static std::string test_name() {
    const ::testing::UnitTest& unit = *::testing::UnitTest::GetInstance();
    std::string name = "test";
    if (const ::testing::TestInfo* info = unit.current_test_info())
      name = std::string(info->test_suite_name()) + "." + info->name();
    else if (const ::testing::TestSuite* suite = unit.current_test_suite())
      name = suite->name();
    for (char& c : name)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-') c = '_';
    return name.substr(0, 120);
  }

  std::filesystem::path path_;
};

}  // namespace imx::test
