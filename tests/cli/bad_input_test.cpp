// Bad input: one clear message naming the culprit, a non-zero exit, and no output file.
#include <cstdlib>
#include <fstream>

#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "scene_fixture.hpp"
#include "temp_dir.hpp"

namespace imx::test {
namespace {

const std::string kQuad = mesh_json("q", R"("primitive": "quad", "size": [50, 50])");

// A 32x32 image of `objects`; `extra`: more top-level members.
std::string scene_with(const std::string& objects, const std::string& extra = "") {
  return with_objects(objects, R"("image": {"width": 32, "height": 32})" + extra);
}

void expect_failure(const TempDir& dir, const std::string& scene_text,
                    const std::vector<std::string>& culprits, const std::string& extra_args = "") {
  dir.write("scene.json", scene_text);
  auto out = dir / "out.png";
  CliResult r =
      run_cli("render " + (dir / "scene.json").string() + " -o " + out.string() + " " + extra_args);
  EXPECT_NE(r.exit_code, 0) << r.output;
  for (const std::string& c : culprits) EXPECT_NE(r.output.find(c), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  for (auto& entry : std::filesystem::directory_iterator(dir.path()))
    EXPECT_EQ(entry.path().extension() == ".png", false) << "left behind: " << entry.path();
}

TEST(CliBadInput, MalformedJson) {
  TempDir dir;
  expect_failure(dir, R"({"image": {"width": 32,, }})", {"scene.json", "parse"});
}

TEST(CliBadInput, UnknownKeyWithSuggestion) {
  TempDir dir;
  expect_failure(dir, scene_with(kQuad, R"(, "imgae": {})"), {"scene.json", "imgae", "image"});
}

TEST(CliBadInput, WrongType) {
  TempDir dir;
  expect_failure(dir, R"({"image": {"width": "wide"}, "objects": []})",
                 {"scene.json", "image.width", "wide"});
}

TEST(CliBadInput, MissingFile) {
  TempDir dir;
  expect_failure(dir,
                 scene_with(R"({"name": "m", "type": "mesh", "source": {"file": "nowhere.stl"}})"),
                 {"nowhere.stl"});
  CliResult r =
      run_cli("render " + (dir / "absent.json").string() + " -o " + (dir / "x.png").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("absent.json"), std::string::npos) << r.output;
}

TEST(CliBadInput, ZeroOrNegativeSize) {
  TempDir dir;
  expect_failure(dir, R"({"image": {"width": 0, "height": 32}, "objects": []})",
                 {"image.width", "0"});
  expect_failure(dir, scene_with(kQuad), {"image.height", "-5"}, "--set image.height=-5");
}

TEST(CliBadInput, NonFiniteTransform) {
  TempDir dir;
  // JSON has no NaN literal; an overflowing number is the way such values arrive.
  expect_failure(
      dir,
      scene_with(R"({"name": "m", "type": "mesh", "source": {"primitive": "quad", "size": [5, 5]},
                     "transform": {"translate": [1e999, 0, 0]}})"),
      {"scene.json", "1e999"});
  // A degenerate matrix cannot place an object.
  expect_failure(
      dir,
      scene_with(R"({"name": "m", "type": "mesh", "source": {"primitive": "quad", "size": [5, 5]},
                     "transform": {"scale": [1, 0, 1]}})"),
      {"objects[0].transform"});
  // A NaN in a volume file's space directions.
  dir.write("nan.nhdr",
            "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nspace: left-posterior-superior\n"
            "space directions: (nan,0,0) (0,1,0) (0,0,1)\nspace origin: (0,0,0)\n"
            "encoding: raw\ndata file: nan.raw\n");
  dir.write("nan.raw", std::string(8, '\1'));
  expect_failure(dir, scene_with(R"({"name": "v", "type": "volume", "source": {"file": "nan.nhdr"},
                     "transfer_function": {"points": [[0, 1, 1, 1, 1]]}})"),
                 {"nan.nhdr"});
}

TEST(CliBadInput, TruncatedNrrd) {
  TempDir dir;
  dir.write("cut.nrrd",
            "NRRD0004\ntype: short\ndimension: 3\nsizes: 16 16 16\nencoding: raw\n"
            "endian: little\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n"
            "space origin: (0,0,0)\nspace: left-posterior-superior\n\n" +
                std::string(100, '\0'));
  expect_failure(dir, scene_with(R"({"name": "v", "type": "volume", "source": {"file": "cut.nrrd"},
                     "transfer_function": {"points": [[0, 1, 1, 1, 1]]}})"),
                 {"cut.nrrd"});
  CliResult r = run_cli("info " + (dir / "cut.nrrd").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("cut.nrrd"), std::string::npos) << r.output;
}

TEST(CliBadInput, UnknownMethodListsTheAvailableOnes) {
  TempDir dir;
  expect_failure(dir, scene_with(kQuad), {"zslab-wrong", "reference"}, "--method zslab-wrong");
}

TEST(CliBadInput, AThreadCountTbbCannotTakeIsRefused) {
  TempDir dir;
  expect_failure(dir, scene_with(kQuad), {"--threads", "2147483647", "1024"},
                 "--threads 2147483647");
}

TEST(CliBadInput, OutputOntoAFifoIsRefusedAndTheFifoKept) {
  TempDir dir;
  dir.write("scene.json", scene_with(kQuad));
  const auto out = dir / "out.png";
  ASSERT_EQ(std::system(("mkfifo " + out.string()).c_str()), 0);
  CliResult r = run_cli("render " + (dir / "scene.json").string() + " -o " + out.string());
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("is a FIFO"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::is_fifo(out));
}

TEST(CliBadInput, ImagesOfDifferentSizesAreNamedWithTheirSizes) {
  TempDir dir;
  dir.write("scene.json", scene_with(kQuad));
  const std::string scene = (dir / "scene.json").string();
  ASSERT_EQ(run_cli("render " + scene + " -o " + (dir / "a.png").string()).exit_code, 0);
  ASSERT_EQ(run_cli("render " + scene + " --width 16 -o " + (dir / "b.png").string()).exit_code, 0);
  CliResult r = run_cli("compare " + (dir / "a.png").string() + " " + (dir / "b.png").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("a.png is 32x32"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("b.png is 16x32"), std::string::npos) << r.output;
}

TEST(CliBadInput, MemoryBudgetIsCheckedBeforeAllocating) {
  TempDir dir;
  dir.write("scene.json", scene_with(kQuad));
  CliResult r = run_cli("--max-memory 1K render " + (dir / "scene.json").string() + " -o " +
                        (dir / "out.png").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("a 32x32 image needs 32.0 KiB, more than the memory budget of 1.0 KiB"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.png"));
  r = run_cli("--max-memory 1M render " + (dir / "scene.json").string() + " -o " +
              (dir / "out.png").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = run_cli("--max-memory 2x render " + (dir / "scene.json").string() + " -o x.png");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("2x is not a size"), std::string::npos) << r.output;
}

TEST(CliBadInput, APrimitiveIsTessellatedWithinTheBudgetAndItsLimits) {
  TempDir dir;
  const std::string sphere =
      R"({"name": "s", "type": "mesh", "source": {"primitive": "sphere", "radius": 10, "segments": )";
  dir.write("scene.json", scene_with(sphere + "1024}}"));
  CliResult r = run_cli("--max-memory 1M render " + (dir / "scene.json").string() + " -o " +
                        (dir / "out.png").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  for (const char* part : {"objects[0].source: sphere: segments 1024", "memory budget of 1.0 MiB"})
    EXPECT_NE(r.output.find(part), std::string::npos) << part << " missing from: " << r.output;
  // 4096 segments took over 5 GB; the most is now 1024.
  dir.write("scene.json", scene_with(sphere + "4096}}"));
  r = run_cli("render " + (dir / "scene.json").string() + " -o " + (dir / "out.png").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("objects[0].source.segments: 4096 is not in [3, 1024]"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.png"));
}

// Within the budget but beyond what the machine gives (here: an address-space limit), the
// error names the object's JSON path, its input and the budget, not "std::bad_alloc".
TEST(CliBadInput, OutOfMemoryNamesTheInputAndTheBudget) {
#ifdef IMX_SANITIZED
  GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space: it cannot start under an "
                  "address-space limit, and it aborts rather than throw std::bad_alloc";
#endif
  TempDir dir;
  dir.write("scene.json",
            scene_with(R"({"name": "big", "type": "volume", "source": {"phantom": "ct-head",)"
                       R"( "size": 640}, "transfer_function": {"preset": "ct-bone"}})"));
  CliResult r =
      run_cli("render " + (dir / "scene.json").string() + " -o " + (dir / "out.png").string(),
              "ulimit -v 250000; ");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  for (const char* part : {"objects[0]", "phantom 'ct-head'", "out of memory", "memory budget of"})
    EXPECT_NE(r.output.find(part), std::string::npos) << part << " missing from: " << r.output;
  EXPECT_EQ(r.output.find("bad_alloc"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.png"));
}

// Running out of memory where no reader catches it (here: rendering a volume file under a
// small address space) names the command's inputs, once: not "intermix: error: intermix:".
TEST(CliBadInput, OutOfMemoryOutsideAReaderNamesTheInputs) {
#ifdef IMX_SANITIZED
  GTEST_SKIP() << "AddressSanitizer cannot start under an address-space limit";
#endif
  TempDir dir;
  const std::string volume = (dir / "head.nii.gz").string();
  ASSERT_EQ(run_cli("phantom ct-head --size 256 -o " + volume).exit_code, 0);
  const CliResult r =
      run_cli("render " + volume + " --width 64 --height 64 --set render.gradients=precomputed" +
                  " -o " + (dir / "out.png").string(),
              "ulimit -v 100000; ");  // the gradient copy (32 MiB of int16 voxels) does not fit
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(volume + ": out of memory"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("error: intermix:"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.png"));
}

TEST(CliBadInput, APngClaimingHugeDimensionsIsRefusedBeforeDecoding) {
  TempDir dir;
  // Signature, IHDR for 65536 x 32768 RGBA, a 10-byte IDAT and IEND, 69 bytes in all (CRCs of
  // IHDR and IEND are right; spng reads the header before it checks the rest).
  const unsigned char png[] = {
      0x89, 'P',  'N',  'G',  0x0d, 0x0a, 0x1a, 0x0a, 0,    0,    0,   13,  'I', 'H',
      'D',  'R',  0,    1,    0,    0,    0,    0,    0x80, 0,    8,   6,   0,   0,
      0,    0x5d, 0xb0, 0x2f, 0x17, 0,    0,    0,    10,   'I',  'D', 'A', 'T', 0x78,
      0x9c, 0x63, 0x60, 0x00, 0x00, 0x00, 0x02, 0x00, 0x01, 0,    0,   0,   0,   0,
      0,    0,    0,    'I',  'E',  'N',  'D',  0xae, 0x42, 0x60, 0x82};
  std::ofstream(dir / "bomb.png", std::ios::binary)
      .write(reinterpret_cast<const char*>(png), sizeof png);
  CliResult r =
      run_cli("compare " + (dir / "bomb.png").string() + " " + (dir / "bomb.png").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("bomb.png"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("cannot inflate to that much"), std::string::npos) << r.output;
}

// A compressed volume whose claim the budget cannot hold whole is refused before it is read,
// in one line naming the file, the claim and the budget: it was rendered in bricks, each brick
// inflating the whole stream again (an 8 MB .nii.gz claiming 8 GiB ran on past 90 s).
TEST(CliBadInput, ACompressedVolumeOverTheBudgetIsRefusedNotBricked) {
  TempDir dir;
  const std::string volume = (dir / "head.nii.gz").string();
  ASSERT_EQ(run_cli("phantom ct-head --size 128 -o " + volume).exit_code, 0);  // 2.4 MiB
  const CliResult r = run_cli("--max-memory 4M render " + volume + " --width 32 --height 32 -o " +
                              (dir / "out.png").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  for (const char* part : {"head.nii.gz", "gzip voxel data claims 2.4 MiB",
                           "half the memory budget of 4.0 MiB", "decompress the file"})
    EXPECT_NE(r.output.find(part), std::string::npos) << part << " missing from: " << r.output;
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << "more than one line: " << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.png"));
}

TEST(CliBadInput, RangeErrorsPrintShortBounds) {
  CliResult r = run_cli("compare a.png b.png --scale 1e400");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("1e400 is not in [1e-06, 1e+06]"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("17976931348623157"), std::string::npos) << r.output;
  r = run_cli("render x.json -o x.png --spp 5000");
  EXPECT_NE(r.output.find("5000 is not in [1, 1024]"), std::string::npos) << r.output;
}

TEST(CliBadInput, WhatAMethodRefusesNamesTheSceneFile) {
  TempDir dir;
  const std::string fog =
      R"({"name": "fog", "type": "volume", "source": {"phantom": "cube", "size": 8},
          "transfer_function": {"points": [[0, 1, 1, 1, 0.1]]}})";
  expect_failure(dir, scene_with(fog, R"(, "render": {"step_mm": 1e-5})"),
                 {(dir / "scene.json").string() + ": render.step_mm gives a ray step of 1e-05 mm",
                  "volume 'fog'", "more than the 131072 allowed"},
                 "--method mdvr");
  expect_failure(dir, scene_with(fog, R"(, "render": {"layers": 64})"),
                 {"render.layers: 64 is not in [4, 16]"});
}

}  // namespace
}  // namespace imx::test
