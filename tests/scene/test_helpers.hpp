// Helpers for the scene tests: parsing and error capture, temporary folders and mesh topology
// checks.
#pragma once
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"
#include "intermix/mesh.hpp"
#include "intermix/scene.hpp"

namespace imx::test {

// The message of the imx::Error that fn throws, or "(no error)".
inline std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// A scene from JSON text, named "scene.json" in its errors.
inline Scene parse(const std::string& text, const std::vector<std::string>& overrides = {},
                   const std::filesystem::path& base_dir = {}) {
  return parse_scene(text, base_dir, "scene.json", overrides);
}

// The error parsing `text` gives, after checking that it is one line: a message per failure.
inline std::string parse_error(const std::string& text,
                               const std::vector<std::string>& overrides = {},
                               const std::filesystem::path& base_dir = {}) {
  std::string message = error_of([&] { parse(text, overrides, base_dir); });
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  return message;
}

#define EXPECT_CONTAINS(text, part) \
  EXPECT_NE(std::string(text).find(part), std::string::npos) << "message: " << (text)

// A fresh folder under the system temporary folder, removed at the end of the test.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("imx_scene_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
             std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    std::filesystem::path file = path_ / name;
    std::filesystem::create_directories(file.parent_path());
    std::ofstream(file) << text;
    return file;
  }

 private:
  std::filesystem::path path_;
};

// True when, after welding equal positions, every undirected edge is used by exactly two
// triangles in opposite directions (a closed, consistently wound 2-manifold).
inline bool is_closed_and_oriented(const Mesh& mesh, std::string* why = nullptr) {
  std::map<std::tuple<float, float, float>, uint32_t> ids;
  std::vector<uint32_t> weld(mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3& p = mesh.positions[i];
    weld[i] = ids.emplace(std::make_tuple(p.x, p.y, p.z), static_cast<uint32_t>(ids.size()))
                  .first->second;
  }
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const glm::uvec3& t : mesh.triangles) {
    uint32_t v[3] = {weld[t.x], weld[t.y], weld[t.z]};
    for (int e = 0; e < 3; ++e) directed[{v[e], v[(e + 1) % 3]}]++;
  }
  for (const auto& [edge, count] : directed) {
    auto back = directed.find({edge.second, edge.first});
    if (count != 1 || back == directed.end() || back->second != 1) {
      if (why)
        *why = "edge " + std::to_string(edge.first) + "-" + std::to_string(edge.second) + " used " +
               std::to_string(count) + " times, reverse " +
               std::to_string(back == directed.end() ? 0 : back->second);
      return false;
    }
  }
  return true;
}

// Enclosed volume by the divergence theorem: positive when the triangles face outward.
inline double signed_volume(const Mesh& mesh) {
  double sum = 0.0;
  for (const glm::uvec3& t : mesh.triangles) {
    glm::dvec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
    sum += glm::dot(a, glm::cross(b, c)) / 6.0;
  }
  return sum;
}

}  // namespace imx::test
