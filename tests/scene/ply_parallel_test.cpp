// Binary PLY vertices and triangles are read on every core: the same mesh as the one-core
// path of an ASCII copy, and the same messages for bad values.
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "io/mesh/ply_reader.hpp"
#include "mesh_random.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

template <class T>
void put(std::string& out, T value) {
  static_assert(std::endian::native == std::endian::little);
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

const char* kHeader =
    "element vertex {}\nproperty float x\nproperty float y\nproperty float z\n"
    "property float nx\nproperty float ny\nproperty float nz\nproperty uchar red\n"
    "property uchar green\nproperty uchar blue\nelement face {}\n"
    "property list uchar int vertex_indices\nend_header\n";

// The mesh as a binary and as an ASCII PLY file, with normals and 8-bit colours.
std::string ply_of(const Mesh& m, bool binary) {
  std::string s = std::string("ply\nformat ") + (binary ? "binary_little_endian" : "ascii") +
                  " 1.0\n" +
                  fmt::format(fmt::runtime(kHeader), m.positions.size(), m.triangles.size());
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const glm::vec3 p = m.positions[i], n = glm::vec3(p.y, p.z, p.x);
    const uint8_t r = static_cast<uint8_t>(i % 256), g = 7, b = 200;
    if (binary) {
      for (float c : {p.x, p.y, p.z, n.x, n.y, n.z}) put(s, c);
      for (uint8_t c : {r, g, b}) put(s, c);
    } else {
      // As doubles: the text then holds each float's exact value.
      for (float c : {p.x, p.y, p.z, n.x, n.y, n.z}) s += fmt::format("{} ", double{c});
      s += fmt::format("{} {} {}\n", r, g, b);
    }
  }
  for (const glm::uvec3& t : m.triangles) {
    if (binary) {
      put<uint8_t>(s, 3);
      for (int k = 0; k < 3; ++k) put(s, static_cast<int32_t>(t[k]));
    } else {
      s += fmt::format("3 {} {} {}\n", t.x, t.y, t.z);
    }
  }
  return s;
}

bool same_bits(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  // memcmp of an empty vector's null data is undefined, even for 0 bytes.
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0);
}

TEST(PlyParallel, BinaryReadsAsTheAsciiCopy) {
  const Mesh m = test::random_mesh(21, 20000, 50000, 120000, false);
  test::TempDir dir;
  const Mesh binary = detail::read_ply(dir.write("b.ply", ply_of(m, true)));
  const Mesh ascii = detail::read_ply(dir.write("a.ply", ply_of(m, false)));
  EXPECT_TRUE(same_bits(binary.positions, m.positions));
  EXPECT_TRUE(binary.triangles == m.triangles);
  EXPECT_TRUE(same_bits(binary.positions, ascii.positions));
  EXPECT_TRUE(same_bits(binary.normals, ascii.normals));
  EXPECT_TRUE(same_bits(binary.colors, ascii.colors));
  EXPECT_TRUE(binary.triangles == ascii.triangles);
  EXPECT_EQ(binary.colors.size(), m.positions.size());
}

TEST(PlyParallel, BadValuesGiveTheOneCoreMessages) {
  const Mesh m = test::random_mesh(22, 2000, 5000, 12000, false);
  test::TempDir dir;
  Mesh bad = m;
  bad.positions[3000].y = std::numeric_limits<float>::infinity();
  bad.positions[4000].z = std::numeric_limits<float>::quiet_NaN();
  test::expect_error([&] { detail::read_ply(dir.write("v.ply", ply_of(bad, true))); },
                     {"v.ply", "vertex 3000 has a non-finite coordinate"});
  // A negative index: the one-core path names the face.
  std::string s = ply_of(m, true);
  const size_t face_bytes = 13, faces_at = s.size() - m.triangles.size() * face_bytes;
  const int32_t minus_one = -1;
  std::memcpy(s.data() + faces_at + 7000 * face_bytes + 5, &minus_one, 4);
  test::expect_error([&] { detail::read_ply(dir.write("f.ply", s)); },
                     {"f.ply", "face 7000 of 12000 has a bad vertex index -1"});
}

TEST(PlyParallel, AQuadAmongTrianglesIsAFan) {
  Mesh m = test::random_mesh(23, 100, 300, 1000, false);
  std::string s = ply_of(m, true);
  // Face 500 becomes a quad: its list grows by one index, so the faces no longer have one size.
  const size_t faces_at = s.size() - m.triangles.size() * 13, at = faces_at + 500 * 13;
  s[at] = 4;
  std::string extra;
  put<int32_t>(extra, 9);
  s.insert(at + 13, extra);
  test::TempDir dir;
  const Mesh got = detail::read_ply(dir.write("q.ply", s));
  ASSERT_EQ(got.triangles.size(), m.triangles.size() + 1);
  EXPECT_EQ(got.triangles[500], m.triangles[500]);
  EXPECT_EQ(got.triangles[501], glm::uvec3(m.triangles[500].x, m.triangles[500].z, 9));
  EXPECT_EQ(got.triangles[502], m.triangles[501]);
}

}  // namespace
}  // namespace imx
