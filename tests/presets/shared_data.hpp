// Helpers for the presets tests: the shared data folder, temporary files, error capture and a
// reader of Slicer's presets XML written apart from the generator script.
#pragma once
#include <unistd.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "intermix/error.hpp"

namespace imx::test {

inline std::filesystem::path shared_data(const std::string& name) {
  return std::filesystem::path(IMX_SHARED_DATA) / name;
}

inline std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

#define EXPECT_CONTAINS(text, part) \
  EXPECT_NE(std::string(text).find(part), std::string::npos) << "message: " << (text)

// A fresh folder for one test, removed at its end.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("imx_presets_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
             std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    std::filesystem::path file = path_ / name;
    std::ofstream(file, std::ios::binary) << text;
    return file;
  }

 private:
  std::filesystem::path path_;
};

// Each <VolumeProperty .../> element of Slicer's presets file as its attributes.
inline std::vector<std::map<std::string, std::string>> read_slicer_presets_xml(
    const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  std::vector<std::map<std::string, std::string>> out;
  for (size_t at = s.find("<VolumeProperty"); at != std::string::npos;
       at = s.find("<VolumeProperty", at + 1)) {
    const size_t end = s.find("/>", at);
    std::map<std::string, std::string> attributes;
    size_t i = at + std::string("<VolumeProperty").size();
    while (true) {
      const size_t eq = s.find("=\"", i);
      if (eq == std::string::npos || eq > end) break;
      size_t key_start = s.rfind(' ', eq) + 1;
      const size_t close = s.find('"', eq + 2);
      attributes[s.substr(key_start, eq - key_start)] = s.substr(eq + 2, close - eq - 2);
      i = close + 1;
    }
    out.push_back(attributes);
  }
  return out;
}

// "N v1 ... vN" as its N numbers.
inline std::vector<double> slicer_numbers(const std::string& text) {
  std::istringstream in(text);
  size_t n = 0;
  in >> n;
  std::vector<double> out;
  std::string token;
  while (in >> token) out.push_back(std::strtod(token.c_str(), nullptr));
  EXPECT_EQ(out.size(), n) << text;
  return out;
}

}  // namespace imx::test
