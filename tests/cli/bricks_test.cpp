// Volumes too large to hold whole: `render` renders them brick by brick (also when --bricks N
// asks), and `convert -o X.zarr` writes an OME-Zarr pyramid slab by slab, which reads back equal.
#include <algorithm>
#include <filesystem>
#include <limits>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "intermix/error.hpp"
#include "intermix/image.hpp"
#include "intermix/io.hpp"
#include "intermix/metrics.hpp"
#include "io/zarr/ome_zarr_reader.hpp"
#include "ome_zarr_files.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

const char* kSmall = " --width 64 --height 64 -o ";

// run_cli without --quiet: the notes and the summary line are what is checked.
test::CliResult run_loud(const std::string& args) {
  return test::run_shell(std::string(IMX_CLI_PATH) + " " + args + " 2>&1");
}

fs::path write_phantom(const test::TempDir& dir) {
  const fs::path nrrd = dir / "head.nrrd";
  const test::CliResult made = run_cli("phantom ct-head --size 96 --raw -o " + nrrd.string());
  EXPECT_EQ(made.exit_code, 0) << made.output;
  return nrrd;
}

TEST(CliBricks, AFrameInBricksIsTheWholeFrame) {
  test::TempDir dir;
  const std::string nrrd = write_phantom(dir).string();
  const fs::path whole = dir / "whole.png", four = dir / "four.png", budget = dir / "budget.png";
  const fs::path scene = dir / "scene.json";
  // The scene a render in bricks chose (its camera frames the whole grid, as the visible part
  // would need every voxel), rendered whole.
  test::CliResult r = run_loud("render " + nrrd + " --bricks 4 --save-scene " + scene.string() +
                               kSmall + four.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(test::contains(r.output, "zslab in 4 bricks")) << r.output;
  r = run_cli("render " + scene.string() + " --method zslab" + kSmall + whole.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // 1.3 MB of voxels against a 1 MiB budget: past half of it, so rendered in bricks unasked.
  r = run_loud("--max-memory 1M render " + nrrd + kSmall + budget.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(test::contains(r.output, "more than half the memory budget")) << r.output;
  EXPECT_TRUE(test::contains(r.output, "rendering in bricks")) << r.output;
  const Image reference = read_png(whole);
  // Bricks cut where their neighbours begin, so a sample is never counted twice or missed:
  // measured 62.4 and 70.3 dB; bricks that also render their aprons give 56 dB (test_dist's
  // LocalComposite), the wrong camera of an outline 19 dB.
  EXPECT_GE(psnr(reference, read_png(four)), 59.0);
  EXPECT_GE(psnr(reference, read_png(budget)), 59.0);
}

// `serve` opens a pyramid too large to hold at its coarse level, then refines: after the
// converged still frame comes one rendered in bricks at full resolution, which equals the
// served scene rendered whole at level 0 up to the bricks' seams (bench/viewer-frames is the
// client).
TEST(CliBricks, TheViewerRefinesACoarseLevelToFullResolution) {
  test::TempDir dir;
  const fs::path nrrd = write_phantom(dir), zarr = dir / "head.zarr";
  test::CliResult r = run_cli("convert " + nrrd.string() + " --chunk 16 -o " + zarr.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path still = dir / "still.png", full = dir / "full.png", whole = dir / "whole.png";
  const fs::path served = dir / "served.json", level0 = dir / "level0.json";
  const fs::path client = fs::path(IMX_BENCH_SCENES_DIR).parent_path() / "viewer-frames";
  r = test::run_shell(fmt::format(
      "/usr/bin/python3 {} --size 64x64 --timeout 300 --save-still {} --save-full {} -- {} "
      "--max-memory 1M serve {} --spp 4 --save-scene {} 2>&1",
      client.string(), still.string(), full.string(), IMX_CLI_PATH, zarr.string(),
      served.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(test::contains(r.output, "full_resolution_s")) << r.output;
  // The served scene at level 0, held whole (no budget), at the frames' size.
  nlohmann::json scene = nlohmann::json::parse(test::read_bytes(served));
  ASSERT_EQ(scene["objects"][0]["source"]["level"], "view");
  scene["objects"][0]["source"].erase("level");
  scene["image"] = {{"width", 64}, {"height", 64}};
  test::write_bytes(level0, scene.dump());
  r = run_cli("render " + level0.string() + " --method zslab --spp 4 -o " + whole.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Image reference = read_png(whole);
  // Measured: 70.3 dB for the full-resolution frame (bricks' seams), 28.6 dB for level 1.
  const double full_db = psnr(reference, read_png(full));
  const double coarse_db = psnr(reference, read_png(still));
  EXPECT_GE(full_db, 59.0);
  EXPECT_LT(coarse_db, full_db - 10.0) << full_db << " dB against " << coarse_db;
}

// --lod: each brick of a pyramid reads the coarsest level whose voxel fits its pixels. Where a
// pixel is smaller than a voxel that is level 0, the same image as bricks at full resolution;
// where pixels are several voxels wide, coarser levels, near the full-resolution image.
TEST(CliBricks, LevelsOfDetailFollowThePixelFootprint) {
  test::TempDir dir;
  const fs::path nrrd = write_phantom(dir), zarr = dir / "head.zarr";
  test::CliResult r = run_cli("convert " + nrrd.string() + " --chunk 16 -o " + zarr.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path scene = dir / "scene.json";
  r = run_cli("render " + zarr.string() + " --save-scene " + scene.string() + kSmall +
              (dir / "whole.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto render = [&](const std::string& options, int size, const std::string& name) {
    const fs::path png = dir / name;
    const test::CliResult out =
        run_loud(fmt::format("render {} {} --width {} --height {} -o {}", scene.string(), options,
                             size, size, png.string()));
    EXPECT_EQ(out.exit_code, 0) << out.output;
    return std::pair{out.output, read_png(png)};
  };
  const auto [fine_log, fine] = render("--lod", 512, "lod512.png");
  EXPECT_TRUE(test::contains(fine_log, "pyramid levels up to 0")) << fine_log;
  EXPECT_EQ(psnr(render("--bricks 8", 512, "b512.png").second, fine),
            std::numeric_limits<double>::infinity());
  const auto [coarse_log, coarse] = render("--lod", 24, "lod24.png");
  EXPECT_FALSE(test::contains(coarse_log, "pyramid levels up to 0")) << coarse_log;
  const Image full = render("--bricks 8", 24, "b24.png").second;
  // Measured 28.9 dB at 24² (level 1 of a sharp bone ramp); level 3 alone is 17.7 dB.
  const double db = psnr(full, coarse);
  EXPECT_GE(db, 22.0);
  EXPECT_LT(db, std::numeric_limits<double>::infinity());
  // A volume that is no pyramid: said, and rendered at full resolution.
  r = run_loud("render " + nrrd.string() + " --lod" + kSmall + (dir / "flat.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(test::contains(r.output, "--lod: no volume is read from an OME-Zarr pyramid"))
      << r.output;
}

TEST(CliBricks, InfoDescribesAGridPastWhatOneVolumeHoldsFromItsHeader) {
  test::TempDir dir;
  // 2048 x 2048 x 1025 uint16: past 2^31 voxels, 8.6 GB of zeros in a sparse file.
  const fs::path nrrd = dir / "huge.nrrd";
  test::write_bytes(nrrd,
                    "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 2048 2048 1025\n"
                    "spacings: 0.1 0.1 0.1\nencoding: raw\nendian: little\n\n");
  fs::resize_file(nrrd, fs::file_size(nrrd) + uint64_t{2048} * 2048 * 1025 * 2);
  const test::CliResult r = run_cli("info " + nrrd.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(test::contains(r.output, "[2048,2048,1025]")) << r.output;
  EXPECT_TRUE(test::contains(r.output, "too large to hold whole")) << r.output;
}

TEST(CliBricks, ConvertWritesAPyramidThatReadsBackEqual) {
  SKIP_WITHOUT_ZARR();
  test::TempDir dir;
  const fs::path nrrd = write_phantom(dir);
  const fs::path zarr = dir / "head.zarr";
  // A small budget: the volume is read slab by slab, by region.
  test::CliResult r =
      run_cli("--max-memory 1M convert " + nrrd.string() + " --chunk 16 -o " + zarr.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const VolumeData source = read_volume(nrrd), level0 = read_volume(zarr);
  EXPECT_EQ(level0.dims, source.dims);
  ASSERT_EQ(level0.type(), source.type());
  const auto& a = std::get<VoxelBuffer<int16_t>>(level0.voxels);
  const auto& b = std::get<VoxelBuffer<int16_t>>(source.voxels);
  EXPECT_TRUE(std::equal(a.data(), a.data() + a.size(), b.data()));
  for (int c = 0; c < 4; ++c)
    for (int r4 = 0; r4 < 4; ++r4)
      EXPECT_NEAR(level0.index_to_world[c][r4], source.index_to_world[c][r4], 1e-9) << c << r4;
  // zarr-python reads every level; level 1 is the 2x2x2 means of level 0 (edges repeated),
  // rounded half away from zero.
  ASSERT_TRUE(test::run_zarr_python(dir, R"PY(
g = zarr.open('head.zarr', mode='r')
a = g['0'][...].astype('f8')
pad = [(0, s % 2) for s in a.shape]
p = np.pad(a, pad, mode='edge')
m = p.reshape(p.shape[0] // 2, 2, p.shape[1] // 2, 2, p.shape[2] // 2, 2).mean(axis=(1, 3, 5))
want = np.sign(m) * np.floor(np.abs(m) + 0.5)
got = g['1'][...].astype('f8')
assert got.shape == want.shape, (got.shape, want.shape)
assert np.array_equal(got, want), np.abs(got - want).max()
assert len(g.attrs['multiscales'][0]['datasets']) == len([k for k in g.array_keys()])
print(len(g.attrs['multiscales'][0]['datasets']))
)PY"));
  // A second convert to the same folder is refused and leaves it as it was.
  r = run_cli("convert " + nrrd.string() + " -o " + zarr.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(test::contains(r.output, "exists")) << r.output;
}

TEST(CliBricks, AnObliqueGridKeepsItsPlacementInEveryLevel) {
  const fs::path flair = test::shared_data("FLAIR.nii.gz");
  SKIP_WITHOUT_SHARED_DATA(flair);
  test::TempDir dir;
  const fs::path zarr = dir / "flair.zarr";
  const test::CliResult r = run_cli("convert " + flair.string() + " -o " + zarr.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const VolumeData source = read_volume(flair);
  const VolumeHeader level0 = read_volume_header(zarr);
  EXPECT_EQ(level0.dims, source.dims);
  for (int c = 0; c < 4; ++c)
    for (int row = 0; row < 4; ++row)
      EXPECT_NEAR(level0.index_to_world[c][row], source.index_to_world[c][row], 1e-9);
  // Level 1's voxel (0, 0, 0) averages voxels 0..1 of level 0 along each axis: its centre is
  // level 0's index (0.5, 0.5, 0.5), wherever the oblique axes point.
  const VolumeData level1 = detail::read_ome_zarr(zarr, 1);
  const glm::dvec4 want = source.index_to_world * glm::dvec4(0.5, 0.5, 0.5, 1.0);
  const glm::dvec4 got = level1.index_to_world * glm::dvec4(0.0, 0.0, 0.0, 1.0);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(got[a], want[a], 1e-9) << a;
  EXPECT_NEAR(glm::length(glm::dvec3(level1.index_to_world[0])),
              2 * glm::length(glm::dvec3(source.index_to_world[0])), 1e-9);
  // A matrix that is not 4 rows of 4 numbers ending 0 0 0 1 is refused by name.
  std::string attrs = test::read_bytes(zarr / ".zattrs");
  const size_t at = attrs.find("\"index_to_world\"");
  ASSERT_NE(at, std::string::npos) << attrs;
  attrs.replace(at, std::string("\"index_to_world\"").size(), "\"index_to_world\": 7, \"x\"");
  test::write_bytes(zarr / ".zattrs", attrs);
  try {
    read_volume_header(zarr);
    ADD_FAILURE() << "accepted a broken matrix";
  } catch (const Error& e) {
    EXPECT_TRUE(test::contains(e.what(), "field 'intermix.index_to_world'")) << e.what();
  }
}

TEST(CliBricks, AFailedConvertLeavesNothing) {
  test::TempDir dir;
  const fs::path nrrd = write_phantom(dir);
  // Cut the data short: the slabs past the cut cannot be read.
  fs::resize_file(nrrd, fs::file_size(nrrd) / 2);
  const test::CliResult r =
      run_cli("--max-memory 1M convert " + nrrd.string() + " -o " + (dir / "cut.zarr").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(test::contains(r.output, "head.nrrd")) << r.output;
  for (const auto& entry : fs::directory_iterator(dir.path()))
    EXPECT_EQ(entry.path().string().find("cut.zarr"), std::string::npos) << entry.path();
}

}  // namespace
}  // namespace imx
