// The movie files intermix writes, by file name extension: container, codec and settings.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace imx {

struct MovieFormat {
  std::string extension;     // ".mp4"
  std::string codec;         // what users know it as: "H.264"
  std::string container;     // libavformat's muxer: "mp4"
  std::string encoder;       // libavcodec's encoder: "libx264"
  std::string pixel_format;  // what the encoder codes: "yuv420p", "bgr0"
  std::string options;       // the encoder's options, "key=value:key=value"
  bool lossless = false;     // the decoded frames equal the given bytes
  bool even_size = false;    // the pixel format halves chroma: width and height must be even
  std::string use;           // one line for listings: what it is for
};

// Every movie format, in the order listings show them (.mp4, .webm, .mkv).
const std::vector<MovieFormat>& movie_formats();

// The formats as a Markdown table (extension, codec, encoder, pixel format, settings, use): what
// docs/figures.md shows between its movie-formats markers (a test checks it).
std::string movie_formats_markdown();

// The format `file`'s extension names (case-insensitive), or null.
const MovieFormat* find_movie_format(const std::filesystem::path& file);

// The same, or imx::Error "FILE: not a movie name; give .mp4 (H.264), ...".
const MovieFormat& movie_format_for(const std::filesystem::path& file);

// Throws imx::Error naming `file` when `format` cannot code a width x height movie (odd sides for
// a chroma-halving format, or no pixel at all).
void check_movie_size(const std::filesystem::path& file, const MovieFormat& format, int width,
                      int height);

}  // namespace imx
