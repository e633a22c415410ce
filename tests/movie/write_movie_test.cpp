// write_movie and MovieEncoder on their own: a frame that fails leaves no file (and an existing
// one as it was), an encoder FFmpeg lacks is named before any frame is rendered, and a lossless
// movie keeps any size and every byte, colours included.
#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/colour.hpp"
#include "expect_error.hpp"
#include "intermix/error.hpp"
#include "movie/movie_encoder.hpp"
#include "movie/movie_format.hpp"
#include "movie/movie_frame.hpp"
#include "movie/movie_reader.hpp"
#include "movie/write_movie.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

// A frame of distinct colours: display ramps in red (x) and green (y), and the frame number in
// blue.
Image pattern(int width, int height, int k) {
  Image image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      image.at(x, y) =
          display_to_linear(glm::vec4(float(x) / width, float(y) / height, 0.1f * k, 1.0f));
  return image;
}

size_t files_in(const fs::path& folder) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder)) ++n;
  return n;
}

TEST(WriteMovie, AFrameThatFailsLeavesNoFileAndKeepsTheOldOne) {
  TempDir dir;
  for (const char* name : {"new.mp4", "old.webm"}) {
    SCOPED_TRACE(name);
    const fs::path movie = dir / name;
    if (std::string(name) == "old.webm") test::write_bytes(movie, "old");
    int rendered = 0;
    EXPECT_THROW(write_movie(movie, 32, 16, 5,
                             [&](int k, const std::function<void(double)>&) {
                               if (k == 3) throw Error("frame 3 failed");
                               ++rendered;
                               return pattern(32, 16, k);
                             }),
                 Error);
    EXPECT_EQ(rendered, 3);
    if (std::string(name) == "old.webm")
      EXPECT_EQ(test::read_bytes(movie), "old");
    else
      EXPECT_FALSE(fs::exists(movie));
  }
  EXPECT_EQ(files_in(dir.path()), 1u);  // old.webm alone: no temporary left
}

TEST(WriteMovie, ErrorsComeBeforeTheFirstFrame) {
  TempDir dir;
  int rendered = 0;
  const auto frame = [&](int k, const std::function<void(double)>&) {
    ++rendered;
    return pattern(33, 16, k);
  };
  test::expect_error([&] { write_movie(dir / "odd.mp4", 33, 16, 2, frame); },
                     {"odd.mp4: H.264 (yuv420p) needs an even width and height, not 33x16"});
  test::expect_error([&] { write_movie(dir / "a.gif", 33, 16, 2, frame); },
                     {"a.gif: not a movie name"});
  test::expect_error([&] { write_movie(dir / "none.mkv", 33, 16, 0, frame); },
                     {"none.mkv: a movie needs at least one frame"});
  MovieFormat missing = *find_movie_format("x.mp4");
  missing.encoder = "imx-no-such-encoder";
  test::expect_error([&] { MovieEncoder::check("x.mp4", missing, 32, 16, 24.0); },
                     {"x.mp4: H.264 needs FFmpeg's imx-no-such-encoder encoder, which this "
                      "FFmpeg (libavcodec "});
  EXPECT_EQ(rendered, 0);
  EXPECT_EQ(files_in(dir.path()), 0u);
}

TEST(WriteMovie, MkvKeepsAnOddSizeAndEveryByte) {
  TempDir dir;
  const fs::path movie = dir / "odd.MKV";  // the extension in any case
  std::vector<double> progress;
  MovieOptions options;
  options.fps = 30;
  options.progress = [&](double f) { progress.push_back(f); };
  write_movie(
      movie, 33, 17, 4,
      [](int k, const std::function<void(double)>& p) {
        p(0.5);
        return pattern(33, 17, k);
      },
      options);
  const DecodedMovie decoded = read_movie(movie);
  EXPECT_EQ(decoded.codec, "ffv1");
  EXPECT_EQ(decoded.width, 33);
  EXPECT_EQ(decoded.height, 17);
  EXPECT_DOUBLE_EQ(decoded.fps, 30.0);
  ASSERT_EQ(decoded.frames.size(), 4u);
  for (int k = 0; k < 4; ++k)
    EXPECT_TRUE(decoded.frames[k] == movie_frame_rgb8(pattern(33, 17, k)));
  ASSERT_FALSE(progress.empty());
  EXPECT_DOUBLE_EQ(progress.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));
}

// H.264 and VP9 code in BT.709 and tag it: the ramps come back within two levels on average.
TEST(WriteMovie, Mp4AndWebmKeepTheColours) {
  TempDir dir;
  for (const char* name : {"ramp.mp4", "ramp.webm"}) {
    SCOPED_TRACE(name);
    write_movie(dir / name, 64, 32, 3,
                [](int k, const std::function<void(double)>&) { return pattern(64, 32, k); });
    const DecodedMovie decoded = read_movie(dir / name);
    ASSERT_EQ(decoded.frames.size(), 3u);
    for (int k = 0; k < 3; ++k) {
      const std::vector<uint8_t> expected = movie_frame_rgb8(pattern(64, 32, k));
      int worst = 0;
      double sum = 0.0;
      for (size_t i = 0; i < expected.size(); ++i) {
        const int error = std::abs(int(decoded.frames[k][i]) - int(expected[i]));
        worst = std::max(worst, error);
        sum += error;
      }
      EXPECT_LE(worst, 12) << "frame " << k;
      // A matrix or range other than the one the stream is tagged with is off by 7 or more.
      EXPECT_LE(sum / expected.size(), 2.0) << "frame " << k;
    }
  }
}

// Where the image is not opaque, a movie shows it over black (it has no alpha).
TEST(WriteMovie, AFrameIsTheImageOverBlack) {
  Image image(2, 1);
  image.at(0, 0) = glm::vec4(0.5f, 0.25f, 0.0f, 1.0f);
  image.at(1, 0) = glm::vec4(0.5f, 0.0f, 0.0f, 0.5f);  // premultiplied: linear 0.5 red over black
  const std::vector<uint8_t> rgb = movie_frame_rgb8(image);
  ASSERT_EQ(rgb.size(), 6u);
  EXPECT_EQ(rgb[0], 188);  // sRGB of linear 0.5
  EXPECT_EQ(rgb[1], 137);  // of 0.25
  EXPECT_EQ(rgb[2], 0);
  EXPECT_EQ(rgb[3], 188);
  EXPECT_EQ(rgb[4], 0);
}

// docs/figures.md's table of movie formats is the one the code has.
TEST(MovieFormats, TheDocsTableIsTheCodes) {
  const std::string docs = test::read_bytes(std::filesystem::path(IMX_EXAMPLES_DIR).parent_path() /
                                            "docs" / "figures.md");
  const std::string begin = "<!-- movie-formats:begin -->\n", end = "<!-- movie-formats:end -->";
  const size_t b = docs.find(begin), e = docs.find(end);
  ASSERT_TRUE(b != std::string::npos && e != std::string::npos && b < e)
      << "docs/figures.md has no movie-formats markers";
  EXPECT_EQ(docs.substr(b + begin.size(), e - b - begin.size()), movie_formats_markdown())
      << "docs/figures.md's movie table differs from movie_formats(): paste the expected text "
         "between its markers";
}

}  // namespace
}  // namespace imx
