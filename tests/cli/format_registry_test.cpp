// The format registry: what it generates (the README's table, `info --formats`, the fuzz seeds)
// matches what is committed, and files are known, refused or redirected by it.
#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "expect_error.hpp"
#include "intermix/formats.hpp"
#include "intermix/io.hpp"
#include "io/streams/gzip.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

const std::filesystem::path kRoot = std::filesystem::path(IMX_EXAMPLES_DIR).parent_path();

// The lines between two markers of a file.
std::string between(const std::string& text, const std::string& begin, const std::string& end) {
  const size_t b = text.find(begin), e = text.find(end);
  if (b == std::string::npos || e == std::string::npos || e < b) return "(markers missing)";
  return text.substr(b + begin.size() + 1, e - b - begin.size() - 1);
}

// fuzz/seed_patterns.txt as the registry makes it: each fuzz target's seed patterns, in row order.
std::string expected_seed_patterns() {
  std::vector<std::pair<std::string, std::vector<std::string>>> targets;
  for (const FileFormat& f : file_formats()) {
    std::istringstream patterns(f.fuzz_seeds);
    for (std::string p; patterns >> p;) {
      auto it = std::find_if(targets.begin(), targets.end(),
                             [&](const auto& t) { return t.first == f.fuzz_target; });
      if (it == targets.end()) it = targets.insert(targets.end(), {f.fuzz_target, {}});
      if (std::find(it->second.begin(), it->second.end(), p) == it->second.end())
        it->second.push_back(p);
    }
  }
  std::string out =
      "# The seed files of each fuzz target that reads a file format: generated from the format\n"
      "# registry (tests/cli/format_registry_test.cpp prints it when it differs); read by "
      "scripts/fuzz.\n";
  for (const auto& [target, patterns] : targets) {
    out += target;
    for (const std::string& p : patterns) out += " " + p;
    out += "\n";
  }
  return out;
}

TEST(FormatRegistry, ReadmeTableIsTheRegistrys) {
  const std::string readme = test::read_bytes(kRoot / "README.md");
  EXPECT_EQ(between(readme, "<!-- formats:begin -->", "<!-- formats:end -->"),
            file_formats_markdown())
      << "README.md's format table differs from the registry: paste the output of "
         "`build/intermix info --formats --markdown` between its markers";
  const test::CliResult r = test::run_cli("info --formats --markdown");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.output, file_formats_markdown());
}

TEST(FormatRegistry, FuzzSeedsAndTargetsAreTheRegistrys) {
  EXPECT_EQ(test::read_bytes(kRoot / "fuzz/seed_patterns.txt"), expected_seed_patterns())
      << "fuzz/seed_patterns.txt differs from the registry: write the expected text above to it";
  for (const FileFormat& f : file_formats()) {
    EXPECT_TRUE(std::filesystem::exists(kRoot / "fuzz" / (f.fuzz_target + ".cpp")))
        << f.name << " names fuzz target '" << f.fuzz_target << "', which does not exist";
    EXPECT_FALSE(f.reference.empty()) << f.name << " names no reference reader";
    for (const std::string& ext : f.extensions) {
      EXPECT_EQ(ext[0], '.') << f.name;
      EXPECT_TRUE(std::none_of(ext.begin(), ext.end(), [](char c) { return std::isupper(c); }))
          << f.name << ": " << ext << " is not lower case";
    }
  }
}

TEST(FormatRegistry, InfoListsEveryKind) {
  const test::CliResult r = test::run_cli("info --formats");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const FileFormat& f : file_formats())
    EXPECT_TRUE(test::contains(r.output, f.name)) << f.name;
  for (const char* kind : {"volume", "mesh", "surface overlay", "transform", "label table"})
    EXPECT_TRUE(test::contains(r.output, kind)) << kind;
}

TEST(FormatRegistry, UnknownFileNamesItsWholeSuffixAndEveryKind) {
  test::TempDir dir;
  const std::filesystem::path file = dir.path() / "fibres.fib.gz";
  test::write_bytes(file, "not a tractogram");
  const std::vector<std::string> commands = {"info ",
                                             "render -o " + (dir.path() / "x.png").string() + " "};
  for (const std::string& command : commands) {
    const test::CliResult r = test::run_cli(command + file.string());
    EXPECT_NE(r.exit_code, 0);
    for (const char* part : {"'.fib.gz' is not a format intermix reads", "volumes:", ".nii.gz",
                             "meshes:", ".obj", "surface overlays", ".annot"})
      EXPECT_TRUE(test::contains(r.output, part)) << command << ": " << part << "\n" << r.output;
  }
  // A text file is no transform or colour table for its ".txt" alone.
  test::write_bytes(dir.path() / "notes.txt", "x");
  const test::CliResult text = test::run_cli("info " + (dir.path() / "notes.txt").string());
  EXPECT_TRUE(test::contains(text.output, "'.txt' is not a format intermix reads")) << text.output;
  test::expect_error([&] { read_volume(file); }, {"'.fib.gz' is not a volume format"});
  test::expect_error([&] { read_mesh(file); }, {"'.fib.gz' is not a mesh format"});
}

TEST(FormatRegistry, AFileThatCannotStandAloneSaysWhatItNeeds) {
  test::TempDir dir;
  // A curvature file is known by its magic number, whatever its name.
  const std::filesystem::path curv = dir.path() / "lh.curv";
  test::write_bytes(curv, std::string("\xff\xff\xff", 3) + std::string(12, '\0'));
  const test::CliResult r = test::run_cli("info " + curv.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(test::contains(r.output, "lh.curv is a surface overlay"));
  EXPECT_TRUE(
      test::contains(r.output, "give it after its surface (intermix render lh.pial lh.curv)"))
      << r.output;
  // With its surface beside it, the example names that surface.
  std::filesystem::create_directory(dir.path() / "subject");
  test::write_bytes(dir.path() / "subject/lh.curv", test::read_bytes(curv));
  test::write_bytes(dir.path() / "subject/lh.white", "a surface by its name");
  const test::CliResult beside = test::run_cli("info " + (dir.path() / "subject/lh.curv").string());
  EXPECT_TRUE(test::contains(beside.output, "(intermix render lh.white lh.curv)")) << beside.output;
  const std::filesystem::path lta = dir.path() / "reg.lta";
  test::write_bytes(lta, "# transform\n");
  const test::CliResult t = test::run_cli("info " + lta.string());
  EXPECT_NE(t.exit_code, 0);
  EXPECT_TRUE(test::contains(t.output, "reg.lta is a transform (FreeSurfer LTA)")) << t.output;
}

TEST(FormatRegistry, GzipOfAMeshReadsAsTheMesh) {
  test::TempDir dir;
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\n";
  test::write_bytes(dir.path() / "m.obj", obj);
  {
    std::ofstream out(dir.path() / "m.obj.gz", std::ios::binary);
    detail::gzip(std::span(reinterpret_cast<const uint8_t*>(obj.data()), obj.size()), out, 6,
                 "m.obj.gz");
  }
  const Mesh plain = read_mesh(dir.path() / "m.obj");
  const Mesh gzipped = read_mesh(dir.path() / "m.obj.gz");
  EXPECT_EQ(gzipped.positions, plain.positions);
  EXPECT_EQ(gzipped.triangles, plain.triangles);
  EXPECT_TRUE(is_mesh_file(dir.path() / "m.obj.gz"));
  // A broken gzip names the user's file, never the temporary copy.
  test::write_bytes(dir.path() / "bad.obj.gz", std::string("\x1f\x8b\x08\x00garbage", 12));
  const std::string message = test::error_of([&] { read_mesh(dir.path() / "bad.obj.gz"); });
  EXPECT_TRUE(test::contains(message, (dir.path() / "bad.obj.gz").string())) << message;
  EXPECT_FALSE(test::contains(message, "intermix-gz-")) << message;
}

TEST(FormatRegistry, GzipOfAnAttachedVolumeReadsAsTheVolume) {
  test::TempDir dir;
  const VolumeData phantom = make_phantom("ct-head", 24);
  write_nrrd(phantom, dir.path() / "v.nrrd", false);
  write_metaimage(phantom, dir.path() / "v.mha", false);
  for (const char* name : {"v.nrrd", "v.mha"}) {
    const std::string bytes = test::read_bytes(dir.path() / name);
    const std::filesystem::path gz = dir.path() / (std::string(name) + ".gz");
    {
      std::ofstream out(gz, std::ios::binary);
      detail::gzip(std::span(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()), out, 1,
                   gz.string());
    }
    ASSERT_TRUE(is_volume_file(gz)) << name;
    const VolumeData plain = read_volume(dir.path() / name), inflated = read_volume(gz);
    EXPECT_EQ(inflated.dims, plain.dims) << name;
    EXPECT_EQ(inflated.index_to_world, plain.index_to_world) << name;
    for (int k = 0; k < plain.dims.z; k += 5)
      for (int j = 0; j < plain.dims.y; j += 3)
        for (int i = 0; i < plain.dims.x; i += 2)
          ASSERT_EQ(inflated.value_at(i, j, k), plain.value_at(i, j, k)) << name;
    EXPECT_EQ(read_volume_header(gz).dims, plain.dims) << name;
    const VoxelBox box{{1, 2, 3}, {9, 8, 7}};
    EXPECT_EQ(read_volume_region(gz, box).value_at(2, 2, 2), plain.value_at(3, 4, 5)) << name;
  }
}

}  // namespace
}  // namespace imx
