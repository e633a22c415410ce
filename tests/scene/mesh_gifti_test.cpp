// GIfTI surfaces (.gii): index orders, encodings, byte orders, RAS to LPS, and hostile files.
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "encodings.hpp"
#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "io/mesh/gifti_reader.hpp"
#include "io/mesh/mesh_topology.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::base64;
using test::error_of;

// A tetrahedron off the origin in RAS, outward-wound.
const float kPoints[4][3] = {{10, 20, 30}, {11, 20, 30}, {10, 21, 30}, {10, 20, 31}};
const int32_t kTriangles[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

// The bytes of rows x 3 values in the given order and byte order.
template <class T>
std::string raw(const T (*rows)[3], size_t n, bool column_major, bool big_endian) {
  std::string out;
  for (size_t k = 0; k < 3 * n; ++k) {
    const size_t r = column_major ? k % n : k / 3, c = column_major ? k / n : k % 3;
    char b[sizeof(T)];
    std::memcpy(b, &rows[r][c], sizeof(T));
    if (big_endian) std::reverse(b, b + sizeof(T));
    out.append(b, sizeof(T));
  }
  return out;
}

template <class T>
std::string ascii(const T (*rows)[3], size_t n, bool column_major) {
  std::string out;
  for (size_t k = 0; k < 3 * n; ++k) {
    const size_t r = column_major ? k % n : k / 3, c = column_major ? k / n : k % 3;
    // A column a line when column-major, as libgiftiio writes it (a row a line is nibabel's).
    const size_t line = column_major ? n : 3;
    out += std::to_string(rows[r][c]) + (k % line == line - 1 ? "\n" : " ");
  }
  return out;
}

struct Array {
  std::string intent, type, order = "RowMajorOrder", encoding = "ASCII", endian = "LittleEndian",
                            dims = "Dimensionality=\"2\" Dim0=\"4\" Dim1=\"3\"", data, extra,
                            external;
};

std::string array_xml(const Array& a) {
  return "<DataArray Intent=\"NIFTI_INTENT_" + a.intent + "\" DataType=\"NIFTI_TYPE_" + a.type +
         "\" ArrayIndexingOrder=\"" + a.order + "\" " + a.dims + " Encoding=\"" + a.encoding +
         "\" Endian=\"" + a.endian + "\" ExternalFileName=\"" + a.external +
         "\" ExternalFileOffset=\"\"" + a.extra + ">\n<MetaData/>\n<Data>" + a.data +
         "</Data>\n</DataArray>\n";
}

std::string gifti(const std::vector<Array>& arrays, const std::string& preamble = "") {
  std::string s = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n" + preamble +
                  "<GIFTI Version=\"1.0\" NumberOfDataArrays=\"" + std::to_string(arrays.size()) +
                  "\">\n<MetaData/>\n<LabelTable/>\n";
  for (const Array& a : arrays) s += array_xml(a);
  return s + "</GIFTI>\n";
}

Array points(const std::string& encoding, bool column_major, bool big_endian = false) {
  Array a;
  a.intent = "POINTSET";
  a.type = "FLOAT32";
  a.order = column_major ? "ColumnMajorOrder" : "RowMajorOrder";
  a.encoding = encoding;
  a.endian = big_endian ? "BigEndian" : "LittleEndian";
  if (encoding == "ASCII") a.data = ascii(kPoints, 4, column_major);
  std::string bytes = raw(kPoints, 4, column_major, big_endian);
  if (encoding == "Base64Binary") a.data = base64(bytes);
  if (encoding == "GZipBase64Binary") a.data = base64(test::zlib_compressed(bytes));
  return a;
}

Array triangles(const std::string& encoding, bool column_major, bool big_endian = false) {
  Array a;
  a.intent = "TRIANGLE";
  a.type = "INT32";
  a.order = column_major ? "ColumnMajorOrder" : "RowMajorOrder";
  a.encoding = encoding;
  a.endian = big_endian ? "BigEndian" : "LittleEndian";
  if (encoding == "ASCII") a.data = ascii(kTriangles, 4, column_major);
  std::string bytes = raw(kTriangles, 4, column_major, big_endian);
  if (encoding == "Base64Binary") a.data = base64(bytes);
  if (encoding == "GZipBase64Binary") a.data = base64(test::zlib_compressed(bytes));
  return a;
}

TEST(MeshGifti, EveryEncodingOrderAndByteOrderGivesTheSameSurfaceInLps) {
  test::TempDir dir;
  int n = 0;
  for (const char* encoding : {"ASCII", "Base64Binary", "GZipBase64Binary"})
    for (bool column_major : {false, true})
      for (bool big : {false, true}) {
        if (std::string(encoding) == "ASCII" && big) continue;
        SCOPED_TRACE(std::string(encoding) + (column_major ? " column-major" : " row-major") +
                     (big ? " big-endian" : ""));
        const auto file = dir.write(
            "s" + std::to_string(n++) + ".gii",
            gifti({triangles(encoding, column_major, big), points(encoding, !column_major, big)}));
        const Mesh raw_mesh = detail::read_gifti(file);
        ASSERT_EQ(raw_mesh.positions.size(), 4u);
        for (int i = 0; i < 4; ++i)
          EXPECT_EQ(raw_mesh.positions[i], glm::vec3(kPoints[i][0], kPoints[i][1], kPoints[i][2]));
        ASSERT_EQ(raw_mesh.triangles.size(), 4u);
        for (int f = 0; f < 4; ++f)
          EXPECT_EQ(raw_mesh.triangles[f],
                    glm::uvec3(kTriangles[f][0], kTriangles[f][1], kTriangles[f][2]));
        const MeshFile read = read_mesh_file(file);
        EXPECT_EQ(read.info.space, MeshSpace::ras);
        EXPECT_EQ(read.info.space_source, MeshSpaceSource::format);
        for (const glm::vec3& p : read.mesh.positions) {
          EXPECT_TRUE(p.x == -10.0f || p.x == -11.0f);  // RAS x and y negated
          EXPECT_TRUE(p.y == -20.0f || p.y == -21.0f);
        }
        const MeshTopology topology = check_closed(read.mesh);
        EXPECT_TRUE(topology.closed());
        EXPECT_NEAR(topology.signed_volume, 1.0 / 6.0, 1e-5);
      }
}

TEST(MeshGifti, OtherArraysAroundTheSurfaceAreRead) {
  // A per-vertex shape array before the surface (libgiftiio crashes when told to skip one).
  test::TempDir dir;
  Array shape;
  shape.intent = "SHAPE";
  shape.type = "FLOAT32";
  shape.dims = "Dimensionality=\"1\" Dim0=\"4\"";
  shape.data = "0.5 1.5 2.5 3.5";
  const auto file = dir.write(
      "shape.gii", gifti({shape, points("Base64Binary", true), shape, triangles("ASCII", false)}));
  const Mesh m = detail::read_gifti(file);
  ASSERT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.positions[2], glm::vec3(10, 21, 30));
  EXPECT_EQ(m.triangles.size(), 4u);
  shape.data = "0.5 1.5";  // a short array elsewhere in the file is an error too
  EXPECT_CONTAINS(error_of([&] {
                    read_mesh_file(dir.write("short.gii", gifti({points("ASCII", false), shape,
                                                                 triangles("ASCII", false)})));
                  }),
                  "data array 1: the data holds 2 values, the dimensions claim 4");
}

TEST(MeshGifti, TheCoordinateSystemTransformIsNotApplied) {
  // The matrix maps the stored (scanner) coordinates to Talairach space for information: the
  // surface stays where its coordinates put it, over the volume they came from.
  test::TempDir dir;
  std::string text = gifti({points("ASCII", false), triangles("ASCII", false)});
  const std::string matrix =
      "<CoordinateSystemTransformMatrix><DataSpace><![CDATA[NIFTI_XFORM_SCANNER_ANAT]]>"
      "</DataSpace><TransformedSpace><![CDATA[NIFTI_XFORM_TALAIRACH]]></TransformedSpace>"
      "<MatrixData>1 0 0 100 0 1 0 0 0 0 1 0 0 0 0 1</MatrixData>"
      "</CoordinateSystemTransformMatrix>\n";
  text.insert(text.find("<Data>"), matrix);
  const Mesh m = detail::read_gifti(dir.write("xform.gii", text));
  ASSERT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.positions[1], glm::vec3(11, 20, 30));
}

TEST(MeshGifti, ColumnMajorOrderSampleIsClosedAndOutward) {
  SKIP_WITHOUT_SHARED_DATA("ColumnMajorOrder.gii");
  const auto file = test::shared_data("ColumnMajorOrder.gii");
  const Mesh raw_mesh = detail::read_gifti(file);
  EXPECT_EQ(raw_mesh.positions.size(), 5124u);
  EXPECT_EQ(raw_mesh.triangles.size(), 10240u);
  const MeshFile read = read_mesh_file(file);
  const MeshTopology topology = check_closed(read.mesh);
  EXPECT_EQ(topology.open_edges, 0u);      // every edge shared by two triangles
  EXPECT_EQ(topology.unpaired_edges, 0u);  // in opposite directions
  EXPECT_GT(topology.signed_volume, 0.0);  // facing outward
  std::printf("ColumnMajorOrder.gii: %zu vertices, %zu triangles, %.0f mm^3\n",
              raw_mesh.positions.size(), raw_mesh.triangles.size(), topology.signed_volume);
  // Read as if row-major, the same bytes make a tangle: the index order matters.
  Mesh wrong = raw_mesh;
  const size_t n = wrong.triangles.size();
  std::vector<uint32_t> flat(3 * n);
  for (size_t k = 0; k < 3 * n; ++k) flat[k] = raw_mesh.triangles[k % n][k / n];
  for (size_t f = 0; f < n; ++f)
    wrong.triangles[f] = {flat[3 * f], flat[3 * f + 1], flat[3 * f + 2]};
  EXPECT_FALSE(check_closed(wrong).closed());
}

// Where the file-level <MetaData/> of gifti() starts.
size_t meta_at(const std::string& text) {
  return text.find("<MetaData/>");
}

TEST(MeshGifti, BadFilesGetOneClearError) {
  test::TempDir dir;
  const Array good_p = points("Base64Binary", false), good_t = triangles("Base64Binary", false);
  auto with = [](Array a, auto change) {
    change(a);
    return a;
  };
  // A 10 MB run of zeros compresses to about 10 KB: claimed as 4 rows of 3 floats.
  Array bomb = good_p;
  bomb.encoding = "GZipBase64Binary";
  bomb.data = base64(test::zlib_compressed(std::string(10 << 20, '\0')));
  Array huge = good_p;
  huge.dims = "Dimensionality=\"2\" Dim0=\"2000000000\" Dim1=\"3\"";
  struct Case {
    std::string name, text, expected;
  };
  const std::vector<Case> cases = {
      {"no_triangles", gifti({good_p}), "no NIFTI_INTENT_TRIANGLE data array"},
      {"no_points", gifti({good_t}), "no NIFTI_INTENT_POINTSET data array"},
      {"out_of_range",
       gifti({good_p, with(triangles("ASCII", false),
                           [](Array& a) { a.data = "0 1 2\n0 1 3\n0 3 2\n1 2 4\n"; })}),
       "triangle 3 uses vertex 4, but the file has 4 vertices"},
      {"negative",
       gifti({good_p, with(triangles("ASCII", false),
                           [](Array& a) { a.data = "0 1 2\n0 1 3\n0 3 2\n1 2 -1\n"; })}),
       "triangle 3 uses vertex -1"},
      {"four_columns",
       gifti({with(good_p, [](Array& a) { a.dims = "Dimensionality=\"2\" Dim0=\"3\" Dim1=\"4\""; }),
              good_t}),
       "Dim1 is 4, not 3"},
      {"one_dimension",
       gifti({with(good_p, [](Array& a) { a.dims = "Dimensionality=\"1\" Dim0=\"12\""; }), good_t}),
       "Dimensionality 1 is not 2"},
      {"huge", gifti({huge, good_t}), "its dimensions claim more than 1073741824 values"},
      {"huge_other",
       gifti({with(good_p,
                   [](Array& a) {
                     a.intent = "SHAPE";
                     a.dims = "Dimensionality=\"1\" Dim0=\"300000000\"";
                   }),
              good_p, good_t}),
       "data array 0 (NIFTI_INTENT_SHAPE): 300000000 float32 values (1.1 GiB) are more than"},
      {"bomb", gifti({bomb, good_t}), "inflates to more than the 48 bytes"},
      {"short", gifti({with(good_p, [](Array& a) { a.data = a.data.substr(0, 8); }), good_t}),
       "decodes to 6 bytes, the dimensions claim 48"},
      {"short_ascii",
       gifti({good_p, with(triangles("ASCII", false), [](Array& a) { a.data = "0 1 2\n"; })}),
       "holds 3 values, the dimensions claim 12"},
      {"truncated_zlib",
       gifti({with(points("GZipBase64Binary", false),
                   [](Array& a) {
                     a.data =
                         base64(test::zlib_compressed(raw(kPoints, 4, false, false)).substr(0, 20));
                   }),
              good_t}),
       "the compressed data is truncated"},
      {"bad_base64", gifti({with(good_p, [](Array& a) { a.data[3] = '*'; }), good_t}),
       "not base64"},
      {"float_triangles", gifti({good_p, with(good_t, [](Array& a) { a.type = "FLOAT32"; })}),
       "DataType float32 is not an integer type"},
      {"unknown_type", gifti({with(good_p, [](Array& a) { a.type = "COMPLEX64"; }), good_t}),
       "DataType 'NIFTI_TYPE_COMPLEX64'"},
      {"external",
       gifti({with(good_p,
                   [](Array& a) {
                     a.encoding = "ExternalFileBinary";
                     a.data = "";
                   }),
              good_t}),
       "Encoding 'ExternalFileBinary'"},
      {"external_name", gifti({with(good_p, [](Array& a) { a.external = "/etc/passwd"; }), good_t}),
       "external data files (ExternalFileName '/etc/passwd') are not read"},
      {"entities",
       gifti({good_p, good_t},
             "<!DOCTYPE GIFTI [<!ENTITY a \"aaaaaaaaaa\"><!ENTITY b \"&a;&a;&a;&a;\">]>\n"),
       "declares XML entities"},
      {"misplaced_name",
       gifti({good_p, good_t}, "")
           .replace(meta_at(gifti({good_p, good_t})), 11, "<MetaData><Name>x</Name></MetaData>"),
       "<Name> inside <MetaData> (it belongs in <MD>)"},
      {"unknown_element", "<?xml version=\"1.0\"?><GIFTI><Surface/></GIFTI>",
       "<Surface> is not a GIfTI element"},
      {"cdata_data",
       gifti({with(good_p, [](Array& a) { a.data = "<![CDATA[" + a.data + "]]>"; }), good_t}),
       "a <Data> element holds a CDATA section"},
      {"miscounted",
       [&] {
         std::string t = gifti({good_p, good_t});
         return t.replace(t.find("NumberOfDataArrays=\"2\""), 22, "NumberOfDataArrays=\"5\"");
       }(),
       "NumberOfDataArrays is '5', but the file holds 2 data arrays"},
      {"not_xml", "this is not XML", "not a GIfTI file"},
      {"other_root", "<?xml version=\"1.0\"?><NIFTI/>", "the root element is <NIFTI>"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const auto file = dir.write(c.name + ".gii", c.text);
    const std::string message = error_of([&] { read_mesh_file(file); });
    EXPECT_CONTAINS(message, file.string());
    EXPECT_CONTAINS(message, c.expected);
  }
}

}  // namespace
}  // namespace imx
