// intermix render --orbit N and --sweep AXIS -o MOVIE: the movie, decoded back through
// libavcodec, holds the frames `intermix render` gives for each view (within 35 dB PSNR for H.264
// and VP9, equal for lossless FFV1), as many as asked, of the image's size; bad names, sizes and
// option mixes are one clear error that leaves no file.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "intermix/io.hpp"
#include "movie/movie_reader.hpp"
#include "scene_fixture.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::contains;
using test::run_cli;
using test::TempDir;

constexpr int kWidth = 96, kHeight = 64, kFrames = 6;

// PSNR in dB of two 8-bit RGB frames (infinity when equal).
double psnr(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) sum += std::pow(double(a[i]) - double(b[i]), 2);
  if (sum == 0.0) return INFINITY;
  return 10.0 * std::log10(255.0 * 255.0 / (sum / double(a.size())));
}

// The RGB bytes of a PNG `intermix render` wrote (opaque backgrounds: alpha is 255).
std::vector<uint8_t> png_rgb(const fs::path& file) {
  const Image png = read_png(file, true);  // the stored bytes
  std::vector<uint8_t> rgb;
  for (size_t i = 0; i < png.size(); ++i)
    for (int c = 0; c < 3; ++c)
      rgb.push_back(static_cast<uint8_t>(std::lround(png.data()[i][c] * 255.0f)));
  return rgb;
}

// The frame `intermix render SCENE --set ...` gives, as RGB bytes.
std::vector<uint8_t> render_frame(const TempDir& dir, const fs::path& scene, int k,
                                  const std::string& sets) {
  const fs::path png = dir / fmt::format("frame-{}.png", k);
  const test::CliResult r =
      run_cli(fmt::format("render {} --width {} --height {} {} -o {}", scene.string(), kWidth,
                          kHeight, sets, png.string()));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return png_rgb(png);
}

// The small ct-head example (a 48-voxel phantom) with its camera at `eye`.
fs::path head_scene(const TempDir& dir) {
  return test::write_small_example(dir.path(), "ct-head", kWidth, 48);
}

// Frame k of an orbit of the ct-head example's camera (eye (-260, -520, 120), target (0, 0, 5),
// up z) about z: the eye turned by 360 k / N degrees, written out here as a rotation matrix.
std::string orbit_eye(int k) {
  const double a = 2.0 * M_PI * k / kFrames;
  const double x = -260.0, y = -520.0;
  return fmt::format("--set camera.eye=[{},{},120]", x * std::cos(a) - y * std::sin(a),
                     x * std::sin(a) + y * std::cos(a));
}

void expect_movie(const DecodedMovie& movie, const std::string& codec, int frames) {
  EXPECT_EQ(movie.codec, codec);
  EXPECT_EQ(movie.width, kWidth);
  EXPECT_EQ(movie.height, kHeight);
  EXPECT_EQ(movie.frames.size(), static_cast<size_t>(frames));
}

TEST(MovieCli, AnOrbitMp4HoldsTheRendersOfEachView) {
  TempDir dir;
  const fs::path scene = head_scene(dir), movie = dir / "turn.mp4";
  const test::CliResult r =
      run_cli(fmt::format("render {} --orbit {} --width {} --height {} -o {}", scene.string(),
                          kFrames, kWidth, kHeight, movie.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const DecodedMovie decoded = read_movie(movie);
  expect_movie(decoded, "h264", kFrames);
  EXPECT_DOUBLE_EQ(decoded.fps, 24.0);
  ASSERT_EQ(decoded.frames.size(), static_cast<size_t>(kFrames));
  for (int k = 0; k < kFrames; ++k) {
    const std::vector<uint8_t> expected = render_frame(dir, scene, k, orbit_eye(k));
    EXPECT_GE(psnr(decoded.frames[k], expected), 35.0) << "frame " << k;
    // Each frame is its own view: not the next one's (the orbit turns).
    if (k > 0) {
      const std::vector<uint8_t> before = render_frame(dir, scene, 100 + k, orbit_eye(k - 1));
      EXPECT_LT(psnr(decoded.frames[k], before), 30.0) << "frame " << k;
    }
  }
}

TEST(MovieCli, AnOrbitMkvIsLosslessAndTakesAnyFrameRate) {
  TempDir dir;
  const fs::path scene = head_scene(dir), movie = dir / "turn.mkv";
  const test::CliResult r =
      run_cli(fmt::format("render {} --orbit {} --fps 12.5 --width {} --height {} -o {}",
                          scene.string(), kFrames, kWidth, kHeight, movie.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const DecodedMovie decoded = read_movie(movie);
  expect_movie(decoded, "ffv1", kFrames);
  EXPECT_NEAR(decoded.fps, 12.5, 1e-9);
  ASSERT_EQ(decoded.frames.size(), static_cast<size_t>(kFrames));
  for (int k = 0; k < kFrames; ++k)
    EXPECT_TRUE(decoded.frames[k] == render_frame(dir, scene, k, orbit_eye(k))) << "frame " << k;
}

// A scene's annotations are drawn on every frame as `render` draws them through that frame's
// camera; --no-annotations leaves them out.
TEST(MovieCli, AnOrbitDrawsTheScenesAnnotationsInEachFrame) {
  TempDir dir;
  const fs::path scene = head_scene(dir), movie = dir / "ruled.mkv", bare = dir / "bare.mkv";
  const std::string ruler =
      R"(--set 'annotations=[{"kind": "ruler", "points": [[-60, 0, 40], [60, 0, 40]]}]')";
  test::CliResult r = run_cli(fmt::format("render {} {} --orbit 2 --width {} --height {} -o {}",
                                          scene.string(), ruler, kWidth, kHeight, movie.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_cli(fmt::format("render {} {} --no-annotations --orbit 2 --width {} --height {} -o {}",
                          scene.string(), ruler, kWidth, kHeight, bare.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const DecodedMovie ruled = read_movie(movie), plain = read_movie(bare);
  ASSERT_EQ(ruled.frames.size(), 2u);
  ASSERT_EQ(plain.frames.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    const double a = M_PI * k;  // half a turn a frame
    const std::string eye = fmt::format(
        "--set camera.eye=[{},{},120]", -260.0 * std::cos(a) + 520.0 * std::sin(a),
        -260.0 * std::sin(a) - 520.0 * std::cos(a));
    EXPECT_TRUE(ruled.frames[k] == render_frame(dir, scene, k, ruler + " " + eye)) << k;
    EXPECT_FALSE(ruled.frames[k] == plain.frames[k]) << k;
  }
}

// The mpr example's axial plane through its 48-voxel ct-head, moved from the first voxel centre
// to the last along z: the phantom's box as `intermix info` reads it.
TEST(MovieCli, ASweepWebmMovesTheScenesPlaneThroughItsVolume) {
  TempDir dir;
  const fs::path scene = test::write_small_example(dir.path(), "mpr", kWidth, 48);
  const fs::path volume = dir / "head.nii";
  ASSERT_EQ(run_cli("phantom ct-head --size 48 -o " + volume.string()).exit_code, 0);
  const VolumeHeader header = read_volume_header(volume);
  const double z0 = header.index_to_world[3][2];
  const double z1 = z0 + header.index_to_world[2][2] * (header.dims.z - 1);
  const fs::path movie = dir / "sweep.webm";
  const test::CliResult r =
      run_cli(fmt::format("render {} --sweep axial --frames {} --width {} --height {} -o {}",
                          scene.string(), kFrames, kWidth, kHeight, movie.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const DecodedMovie decoded = read_movie(movie);
  expect_movie(decoded, "vp9", kFrames);
  ASSERT_EQ(decoded.frames.size(), static_cast<size_t>(kFrames));
  for (int k = 0; k < kFrames; ++k) {
    const double z = z0 + (z1 - z0) * k / (kFrames - 1);
    const std::vector<uint8_t> expected =
        render_frame(dir, scene, k, fmt::format("--set objects.axial.center=[0,0,{}]", z));
    EXPECT_GE(psnr(decoded.frames[k], expected), 35.0) << "frame " << k << " z " << z;
  }
}

// A volume file alone: the sweep adds an axial plane, hides the volume's rendering and looks
// from below (the reading view's side), as its note says; --save-scene writes that scene, whose
// plane at each position renders the movie's frames.
TEST(MovieCli, ASweepOfAVolumeFileAddsAPlaneAndSavesIt) {
  TempDir dir;
  const fs::path volume = dir / "head.nii", saved = dir / "sweep.json", movie = dir / "s.mkv";
  ASSERT_EQ(run_cli("phantom ct-head --size 48 -o " + volume.string()).exit_code, 0);
  const test::CliResult r = test::run_shell(fmt::format(
      "{} render {} --sweep coronal --frames 3 --width {} --height {} --save-scene {} -o {} 2>&1",
      IMX_CLI_PATH, volume.string(), kWidth, kHeight, saved.string(), movie.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output,
                       "note: --sweep coronal: added plane 'coronal' through volume "
                       "'head' and hid the volume's own rendering"))
      << r.output;
  const nlohmann::json json = nlohmann::json::parse(std::ifstream(saved));
  std::vector<double> centre;
  for (const nlohmann::json& o : json["objects"]) {
    if (o["name"] == "head") {
      EXPECT_EQ(o["visible"], false);
    }
    if (o["name"] == "coronal") centre = o["center"].get<std::vector<double>>();
  }
  ASSERT_EQ(centre.size(), 3u) << json.dump();
  const VolumeHeader header = read_volume_header(volume);
  const glm::dvec3 first = header.index_to_world * glm::dvec4(0, 0, 0, 1);
  const glm::dvec3 last = header.index_to_world *
                          glm::dvec4(header.dims.x - 1, header.dims.y - 1, header.dims.z - 1, 1);
  const DecodedMovie decoded = read_movie(movie);
  ASSERT_EQ(decoded.frames.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const double y = first.y + (last.y - first.y) * k / 2;
    const std::vector<uint8_t> expected = render_frame(
        dir, saved, k,
        fmt::format("--set objects.coronal.center=[{},{},{}]", centre[0], y, centre[2]));
    EXPECT_TRUE(decoded.frames[k] == expected) << "frame " << k;
  }
  // The saved camera looks from anterior (-y) at the coronal plane.
  const std::vector<double> eye = json["camera"]["eye"].get<std::vector<double>>();
  EXPECT_LT(eye[1], first.y - 100.0);
}

TEST(MovieCli, BadNamesSizesAndOptionsAreOneClearErrorAndLeaveNoFile) {
  TempDir dir;
  const fs::path scene = head_scene(dir);
  const std::string s = scene.string();
  const struct {
    std::string args, message;
  } cases[] = {
      {"--orbit 3 -o turn.avi",
       "turn.avi: not a movie name; give .mp4 (H.264), .webm (VP9), .mkv (FFV1, lossless)"},
      {"--orbit 3 --width 95 -o odd.mp4",
       "odd.mp4: H.264 (yuv420p) needs an even width and height, not 95x96; give --width 96 "
       "--height 96, or write .mkv (lossless, any size)"},
      {"--orbit 3 --height 63 -o odd.webm", "odd.webm: VP9 (yuv420p) needs an even width"},
      {"-o still.mp4", "still.mp4: a movie needs --orbit N or --sweep AXIS"},
      {"--orbit 3 --sweep axial -o both.mp4", "--orbit and --sweep: give one"},
      {"--orbit 3 --frames 5 -o frames.mp4", "--frames applies only with --sweep"},
      {"--frames 5 -o frames.png", "--frames applies only with --sweep"},
      {"--sweep axial -o none.mp4", "--sweep axial needs a volume"},  // replaced below
      {"--orbit 3 --linear -o linear.mp4", "--linear does not apply to a movie"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args);
    std::string args = c.args;
    std::string input = s;
    if (contains(args, "none.mp4")) {  // a scene of a mesh only
      input = (dir / "mesh.json").string();
      std::ofstream(input) << R"({"objects": [{"name": "m", "type": "mesh",
                                 "source": {"primitive": "sphere", "radius": 10}}]})";
    }
    const test::CliResult r = test::run_shell(fmt::format(
        "cd {} && {} --quiet render {} {} 2>&1", dir.path().string(), IMX_CLI_PATH, input, args));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_TRUE(contains(r.output, c.message)) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  }
  for (const auto& entry : fs::directory_iterator(dir.path()))
    EXPECT_TRUE(entry.path().extension() == ".json") << entry.path();
}

// The movie plugin missing: one error naming the path tried; an existing movie stays as it was.
TEST(MovieCli, AMissingPluginIsOneErrorAndKeepsTheOldMovie) {
  TempDir dir;
  const fs::path scene = head_scene(dir), movie = dir / "turn.mp4";
  test::write_bytes(movie, "the old movie");
  const test::CliResult r =
      run_cli(fmt::format("render {} --orbit 2 -o {}", scene.string(), movie.string()),
              fmt::format("IMX_MOVIE_PLUGIN={} ", (dir / "missing.so").string()));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(contains(r.output,
                       "movies need the movie plugin (FFmpeg), which cannot be loaded "
                       "(tried: " +
                           (dir / "missing.so").string()))
      << r.output;
  EXPECT_EQ(test::read_bytes(movie), "the old movie");
  size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 2u);  // the scene and the old movie: no temporary left
}

// An output that is one of the inputs (through a link) is refused before anything is written.
TEST(MovieCli, AMovieOverAnInputIsRefused) {
  TempDir dir;
  const fs::path volume = dir / "head.nii", link = dir / "head.mp4";
  ASSERT_EQ(run_cli("phantom ct-head --size 24 -o " + volume.string()).exit_code, 0);
  fs::create_symlink(volume, link);
  const std::string before = test::read_bytes(volume);
  const test::CliResult r = run_cli(fmt::format("render {} --orbit 2 --width 32 --height 32 -o {}",
                                                volume.string(), link.string()));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(contains(r.output, "is an input of this command")) << r.output;
  EXPECT_EQ(test::read_bytes(volume), before);
}

}  // namespace
}  // namespace imx
