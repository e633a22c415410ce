// A movie file decoded back to RGB frames: to check what a movie holds (tests, Python).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace imx {

struct DecodedMovie {
  int width = 0, height = 0;
  double fps = 0.0;
  std::string codec;                         // libavcodec's name: "h264", "vp9", "ffv1"
  std::string pixel_format;                  // as coded: "yuv420p", "gbrp"
  std::vector<std::vector<uint8_t>> frames;  // each height rows of width * 3 bytes (sRGB RGB)
};

// Every frame of the first video stream of `file`, converted to RGB with the colour matrix and
// range the stream states. Throws imx::Error naming the file.
DecodedMovie read_movie(const std::filesystem::path& file);

}  // namespace imx
