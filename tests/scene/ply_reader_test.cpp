#include "io/mesh/ply_reader.hpp"

#include <bit>
#include <cstring>
#include <filesystem>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::error_of;

const std::string kTetraHeader =
    "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "property uchar red\nelement face 3\nproperty list uchar int vertex_indices\n"
    "element edge 2\nproperty int vertex1\nproperty int vertex2\nend_header\n";

// Appends `value` to `out` in the chosen byte order.
template <class T>
void put(std::string& out, T value, bool little) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if (little != (std::endian::native == std::endian::little))
    for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  out.append(bytes, sizeof(T));
}

// Four vertices with an extra colour property, a triangle, a (degenerate) quad, a triangle and
// an "edge" element that the reader must skip; CRLF header lines.
std::string binary_tetra(bool little) {
  std::string s = std::string("ply\r\nformat ") +
                  (little ? "binary_little_endian" : "binary_big_endian") + " 1.0\r\n" +
                  "comment made by a test\r\n" + kTetraHeader;
  const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const auto& p : v) {
    for (float c : p) put(s, c, little);
    put<uint8_t>(s, 200, little);
  }
  put<uint8_t>(s, 3, little);
  for (int i : {0, 2, 1}) put<int32_t>(s, i, little);
  put<uint8_t>(s, 4, little);
  for (int i : {0, 1, 3, 3}) put<int32_t>(s, i, little);
  put<uint8_t>(s, 3, little);
  for (int i : {1, 2, 3}) put<int32_t>(s, i, little);
  for (int i : {0, 1, 1, 2}) put<int32_t>(s, i, little);  // the edges
  return s;
}

TEST(ReadPly, BinaryBothByteOrders) {
  test::TempDir dir;
  for (bool little : {true, false}) {
    auto file = dir.write(little ? "le.ply" : "be.ply", binary_tetra(little));
    Mesh m = detail::read_ply(file);
    ASSERT_EQ(m.positions.size(), 4u);
    EXPECT_EQ(m.positions[3], glm::vec3(0, 0, 1));
    ASSERT_EQ(m.triangles.size(), 4u);  // 1 + 2 (fan of the quad) + 1
    EXPECT_EQ(m.triangles[1], glm::uvec3(0, 1, 3));
    EXPECT_EQ(m.triangles[2], glm::uvec3(0, 3, 3));
    EXPECT_TRUE(m.normals.empty());
  }
}

TEST(ReadPly, AsciiWithNormals) {
  test::TempDir dir;
  auto file = dir.write("n.ply",
                        "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\n"
                        "property double y\nproperty double z\nproperty float nx\n"
                        "property float ny\nproperty float nz\nelement face 1\n"
                        "property list uchar uint vertex_index\nend_header\n"
                        "0 0 0 0 0 2\n1 0 0 0 0 2\n+0 1e0 0 0 0 2\n3 0 1 2\n");
  Mesh m = read_mesh(file);
  ASSERT_EQ(m.triangles.size(), 1u);
  ASSERT_EQ(m.normals.size(), 3u);
  for (const glm::vec3& n : m.normals) EXPECT_EQ(n, glm::vec3(0, 0, 1));
}

TEST(ReadPly, SmoothNormalsWhenTheFileHasNone) {
  test::TempDir dir;
  auto file = dir.write("t.ply", binary_tetra(true));
  Mesh m = read_mesh(file);
  // The corner tetrahedron's edges are all sharper than 60 degrees: each corner splits.
  ASSERT_EQ(m.normals.size(), m.positions.size());
  EXPECT_GT(m.positions.size(), 4u);
  for (const glm::vec3& n : m.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
}

TEST(ReadPly, MalformedFilesAreErrorsNamingTheFile) {
  test::TempDir dir;
  const std::string good = binary_tetra(true);
  std::vector<std::pair<std::string, std::string>> cases = {
      {"ply\nformat ascii 1.0\n", "no end_header"},
      {"ply\nelement vertex 1\nproperty float x\nend_header\n", "no format line"},
      {"plx\n", "not a PLY file"},
      {"ply\nformat ascii 1.0\nproperty float x\nend_header\n", "before any element"},
      {"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n0 0 0\n",
       "the data ends or is malformed in element 'vertex' (2 of 2)"},
      {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
       "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
       "a face uses vertex 7 of 3"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n0 0 abc\n",
       "malformed in element 'vertex'"},
      {"ply\nformat ascii 1.0\nelement vertex 99999999\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n0 0 0\n",
       "exceeds the file size"},
      {"ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float y\n"
       "property float z\nend_header\n",
       "lacks an x, y or z"},
      {good.substr(0, good.size() - 7), "malformed in element 'edge' (2 of 2)"},
      {good.substr(0, good.size() - 40), "malformed in element 'face'"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    auto file = dir.write("bad" + std::to_string(i) + ".ply", cases[i].first);
    std::string msg = error_of([&] { read_mesh(file); });
    EXPECT_CONTAINS(msg, file.string() + ": ");
    EXPECT_CONTAINS(msg, cases[i].second);
  }
}

TEST(ReadPly, EveryTruncationOfTheBunnyIsAnErrorNotACrash) {
  SKIP_WITHOUT_SHARED_DATA("bunny.ply");
  const std::string text = test::read_bytes(test::shared_data("bunny.ply"));
  test::TempDir dir;
  for (size_t cut : {size_t{100}, size_t{300}, text.size() / 3, text.size() - 20}) {
    auto file = dir.write("cut.ply", text.substr(0, cut));
    EXPECT_CONTAINS(error_of([&] { read_mesh(file); }), file.string());
  }
}

}  // namespace
}  // namespace imx
