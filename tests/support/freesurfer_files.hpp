// FreeSurfer test files written byte by byte (big-endian, as FreeSurfer writes them): a closed
// triangle surface on a sphere and a curvature file of given values. The readers themselves are
// checked against nibabel in tests/io.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "temp_dir.hpp"

namespace imx::test {

inline std::string be32(uint32_t v) {
  std::string s(4, '\0');
  for (int i = 0; i < 4; ++i) s[i] = static_cast<char>((v >> (24 - 8 * i)) & 0xFF);
  return s;
}

inline std::string be_float(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return be32(u);
}

// A closed surface of 2 + (rings - 1) * around vertices on a sphere of radius 30 mm: the poles,
// then the rings, a fan of triangles at each pole and two triangles per quad between rings.
inline void write_freesurfer_sphere(const std::filesystem::path& file, int rings, int around) {
  std::vector<glm::vec3> p{{0, 0, 30}};
  for (int r = 1; r < rings; ++r)
    for (int a = 0; a < around; ++a) {
      const double th = M_PI * r / rings, ph = 2 * M_PI * a / around;
      p.emplace_back(30 * std::sin(th) * std::cos(ph), 30 * std::sin(th) * std::sin(ph),
                     30 * std::cos(th));
    }
  p.emplace_back(0, 0, -30);
  std::vector<glm::ivec3> t;
  auto at = [&](int r, int a) { return 1 + (r - 1) * around + (a % around); };
  for (int a = 0; a < around; ++a) t.emplace_back(0, at(1, a), at(1, a + 1));
  for (int r = 1; r + 1 < rings; ++r)
    for (int a = 0; a < around; ++a) {
      t.emplace_back(at(r, a), at(r + 1, a), at(r + 1, a + 1));
      t.emplace_back(at(r, a), at(r + 1, a + 1), at(r, a + 1));
    }
  const int last = static_cast<int>(p.size()) - 1;
  for (int a = 0; a < around; ++a) t.emplace_back(last, at(rings - 1, a + 1), at(rings - 1, a));
  std::string s =
      "\xFF\xFF\xFE"
      "created by test\n\n";
  s += be32(static_cast<uint32_t>(p.size())) + be32(static_cast<uint32_t>(t.size()));
  for (const glm::vec3& q : p) s += be_float(q.x) + be_float(q.y) + be_float(q.z);
  for (const glm::ivec3& q : t)
    s += be32(static_cast<uint32_t>(q.x)) + be32(static_cast<uint32_t>(q.y)) +
         be32(static_cast<uint32_t>(q.z));
  write_bytes(file, s);
}

// A new-format curvature file (magic 0xFFFFFF) of one float per vertex.
inline void write_freesurfer_curv(const std::filesystem::path& file,
                                  const std::vector<float>& values) {
  std::string s = "\xFF\xFF\xFF";
  s += be32(static_cast<uint32_t>(values.size())) + be32(0) + be32(1);
  for (float v : values) s += be_float(v);
  write_bytes(file, s);
}

}  // namespace imx::test
