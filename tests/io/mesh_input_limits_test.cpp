// Mesh inputs against the memory budget and the file rules (issue 32): GIfTI arrays are sized
// from their claims only once the rest of the file can hold them and the budget allows what is
// kept, other arrays stream by; primitives are capped; an OBJ's material file that is a link
// loop or an absolute path is named as such.
#include <zlib.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "encodings.hpp"
#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "io/mesh/gifti_reader.hpp"
#include "peak_growth.hpp"
#include "phantoms/mesh_primitives.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::base64;
using test::expect_error;
using test::TempDir;
using test::write_bytes;

using test::PeakGrowth;

// Restores the default limits when a test ends, whatever it set.
struct LimitsGuard {
  ~LimitsGuard() { set_input_limits({}); }
};

// `n` zero bytes as a zlib stream, made a MiB at a time.
std::string deflated_zeros(uint64_t n) {
  z_stream z{};
  EXPECT_EQ(deflateInit(&z, Z_BEST_SPEED), Z_OK);
  const std::vector<Bytef> zeros(1 << 20, 0);
  std::vector<Bytef> out(1 << 16);
  std::string result;
  int rc = Z_OK;
  while (rc != Z_STREAM_END) {
    const uint64_t piece = std::min<uint64_t>(n, zeros.size());
    n -= piece;
    z.next_in = const_cast<Bytef*>(zeros.data());
    z.avail_in = static_cast<uInt>(piece);
    do {
      z.next_out = out.data();
      z.avail_out = static_cast<uInt>(out.size());
      rc = deflate(&z, n == 0 ? Z_FINISH : Z_NO_FLUSH);
      result.append(reinterpret_cast<const char*>(out.data()), out.size() - z.avail_out);
    } while (z.avail_out == 0);
  }
  deflateEnd(&z);
  return result;
}

std::string data_array(const std::string& intent, const std::string& type, const std::string& dims,
                       const std::string& encoding, const std::string& data,
                       const std::string& endian = "LittleEndian") {
  return fmt::format(
      "<DataArray Intent=\"NIFTI_INTENT_{}\" DataType=\"NIFTI_TYPE_{}\" "
      "ArrayIndexingOrder=\"RowMajorOrder\" {} Encoding=\"{}\" Endian=\"{}\" "
      "ExternalFileName=\"\" ExternalFileOffset=\"\"><Data>{}</Data></DataArray>\n",
      intent, type, dims, encoding, endian, data);
}

const std::string kPoints =
    data_array("POINTSET", "FLOAT32", "Dimensionality=\"2\" Dim0=\"3\" Dim1=\"3\"", "ASCII",
               "0 0 0\n1 0 0\n0 1 0\n");
const std::string kTriangle = data_array(
    "TRIANGLE", "INT32", "Dimensionality=\"2\" Dim0=\"1\" Dim1=\"3\"", "ASCII", "0 1 2\n");

std::string gifti(const std::vector<std::string>& arrays) {
  std::string s = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<GIFTI Version=\"1.0\" "
      "NumberOfDataArrays=\"{}\">\n",
      arrays.size());
  for (const std::string& a : arrays) s += a;
  return s + "</GIFTI>\n";
}

TEST(MeshInputLimits, AGiftiArrayTheSurfaceDoesNotUseCostsNoMemory) {
  // 256 MiB of zeros in 1.5 MB beside a one-triangle surface: libgiftiio held every array
  // (1 GiB of them made 1.07 GB resident), and the budget counted each three times. It is not
  // even inflated now.
  LimitsGuard guard;
  TempDir dir;
  constexpr uint64_t kBytes = uint64_t{256} << 20;
  const std::string shape =
      data_array("SHAPE", "FLOAT32", fmt::format("Dimensionality=\"1\" Dim0=\"{}\"", kBytes / 4),
                 "GZipBase64Binary", base64(deflated_zeros(kBytes)));
  write_bytes(dir / "shape.gii", gifti({shape, kPoints, kTriangle}));
  set_input_limits({uint64_t{64} << 20, false});
  const PeakGrowth peak;
  const Mesh mesh = read_mesh(dir / "shape.gii");
  EXPECT_EQ(mesh.triangles.size(), 1u);
  EXPECT_LT(peak.mib(), 32) << "the unused array was held in memory";
}

TEST(MeshInputLimits, AGiftiClaimTheRestOfTheFileCannotHoldIsRefusedBeforeDecoding) {
  LimitsGuard guard;
  set_input_limits({uint64_t{8} << 30, false});  // the claim and its mesh fit: 2 GiB
  TempDir dir;
  // 1 GiB of float32 vertices claimed for 1 MiB of zeros (about a KB compressed).
  const std::string claim = "Dimensionality=\"2\" Dim0=\"89478485\" Dim1=\"3\"";
  write_bytes(dir / "gz.gii", gifti({data_array("POINTSET", "FLOAT32", claim, "GZipBase64Binary",
                                                base64(deflated_zeros(1 << 20))),
                                     kTriangle}));
  const PeakGrowth peak;
  expect_error([&] { read_mesh(dir / "gz.gii"); },
               {"gz.gii", "data array 0", "1073741820 bytes", "cannot inflate to that much"});
  EXPECT_LT(peak.mib(), 16);
  write_bytes(dir / "b64.gii",
              gifti({data_array("POINTSET", "FLOAT32", claim, "Base64Binary", "AAAA"), kTriangle}));
  expect_error([&] { read_mesh(dir / "b64.gii"); },
               {"b64.gii", "data array 0", "claim 268435455 float32 values", "as base64"});
  write_bytes(dir / "ascii.gii",
              gifti({data_array("POINTSET", "FLOAT32", claim, "ASCII", "0 0 0"), kTriangle}));
  expect_error([&] { read_mesh(dir / "ascii.gii"); },
               {"ascii.gii", "data array 0", "claim 268435455 float32 values", "as text"});
  // An array the surface does not use is not inflated: its compressed size must still be able
  // to make its claim (64 MiB here, with 200 KB of text after it).
  const std::string shape = data_array("SHAPE", "FLOAT32", "Dimensionality=\"1\" Dim0=\"16777216\"",
                                       "GZipBase64Binary", base64(deflated_zeros(1 << 20)));
  std::string filler;
  for (int i = 0; i < 100000; ++i) filler += "0 ";
  write_bytes(dir / "unused.gii",
              gifti({shape,
                     data_array("SHAPE", "FLOAT32", "Dimensionality=\"1\" Dim0=\"100000\"", "ASCII",
                                filler),
                     kPoints, kTriangle}));
  expect_error([&] { read_mesh(dir / "unused.gii"); },
               {"unused.gii", "data array 0", "67108864 bytes", "cannot inflate to that much"});
}

TEST(MeshInputLimits, TheGiftiSurfaceMustFitTheBudgetWithItsMesh) {
  LimitsGuard guard;
  TempDir dir;
  // 8 Mi vertices of float32: 96 MiB as stored and 96 MiB as the mesh's positions; refused
  // at the claim, before the data.
  write_bytes(dir / "big.gii", gifti({data_array("POINTSET", "FLOAT32",
                                                 "Dimensionality=\"2\" Dim0=\"8388608\" Dim1=\"3\"",
                                                 "GZipBase64Binary", "AAAA"),
                                      kTriangle}));
  set_input_limits({uint64_t{128} << 20, false});
  expect_error([&] { read_mesh(dir / "big.gii"); },
               {"big.gii", "data array 0", "8388608 rows of 3 float32 values and the mesh",
                "192.0 MiB", "memory budget of 128.0 MiB"});
}

TEST(MeshInputLimits, GiftiDataIsDecodedByIntermixAloneAndQuietly) {
  TempDir dir;
  // libgiftiio wrote "** bad swapsize 0 for dtype 2" for big-endian bytes, refused ASCII
  // uint32 and wrapped values outside their type.
  const std::string bytes = data_array("LABEL", "UINT8", "Dimensionality=\"1\" Dim0=\"3\"",
                                       "Base64Binary", base64("abc"), "BigEndian");
  const std::string u32 = data_array(
      "TRIANGLE", "UINT32", "Dimensionality=\"2\" Dim0=\"1\" Dim1=\"3\"", "ASCII", "2 1 0\n");
  write_bytes(dir / "quiet.gii", gifti({bytes, kPoints, u32}));
  testing::internal::CaptureStderr();
  const Mesh mesh = detail::read_gifti(dir / "quiet.gii");
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  ASSERT_EQ(mesh.triangles.size(), 1u);
  EXPECT_EQ(mesh.triangles[0], glm::uvec3(2, 1, 0));
  const std::string wide = data_array(
      "TRIANGLE", "INT8", "Dimensionality=\"2\" Dim0=\"1\" Dim1=\"3\"", "ASCII", "0 1 300\n");
  write_bytes(dir / "wide.gii", gifti({kPoints, wide}));
  expect_error([&] { read_mesh(dir / "wide.gii"); },
               {"wide.gii", "data array 1", "value 3 '300' is not an integer within int8's range"});
}

TEST(MeshInputLimits, PrimitivesAreCappedAndCheckedAgainstTheBudget) {
  LimitsGuard guard;
  // 4096 segments made 16 million triangles and more than 5 GB at render time.
  expect_error([] { make_sphere(10.0, 4096); }, {"sphere: segments 4096 is not in [3, 1024]"});
  expect_error([] { make_torus(10.0, 1.0, 1025); }, {"torus: segments 1025 is not in [3, 1024]"});
  EXPECT_EQ(make_sphere(10.0, kMaxPrimitiveSegments).triangles.size(), 1024u * 511 * 2);
  set_input_limits({uint64_t{1} << 20, false});
  expect_error([] { make_sphere(10.0, 1024); },
               {"sphere: segments 1024 (523266 vertices, 1046528 triangles)", "needs 24.0 MiB",
                "memory budget of 1.0 MiB"});
  expect_error([] { make_torus(10.0, 1.0, 512); },
               {"torus: segments 512", "memory budget of 1.0 MiB"});
  EXPECT_EQ(make_cylinder(1.0, 1.0, 1024).triangles.size(), 4096u);
}

TEST(MeshInputLimits, AMaterialFileThatIsALinkLoopIsCalledOne) {
  TempDir dir;
  std::filesystem::create_symlink("b.mtl", dir / "a.mtl");
  std::filesystem::create_symlink("a.mtl", dir / "b.mtl");
  write_bytes(dir / "loop.obj", "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string message = expect_error([&] { read_mesh(dir / "loop.obj"); },
                                           {"loop.obj", "a.mtl", "symbolic link loop"});
  EXPECT_EQ(message.find("outside"), std::string::npos) << message;
}

TEST(MeshInputLimits, AnAbsoluteMaterialPathIsRefusedAsWritten) {
  LimitsGuard guard;
  TempDir dir;
  write_bytes(dir / "abs.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nmtllib /dev/zero\nf 1 2 3\n");
  for (bool external : {false, true}) {
    set_input_limits({0, external});  // assimp would look inside the folder even then
    const std::string message =
        expect_error([&] { read_mesh(dir / "abs.obj"); },
                     {"abs.obj", "line 4", "mtllib '/dev/zero' is an absolute path"});
    EXPECT_EQ(message.find("//dev"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace imx
