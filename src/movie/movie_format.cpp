#include "movie/movie_format.hpp"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx {

const std::vector<MovieFormat>& movie_formats() {
  // H.264 and VP9 at qualities where a render's frames come back near 40 dB PSNR; yuv420p is what
  // browsers and players decode everywhere. FFV1 codes the RGB bytes themselves.
  static const std::vector<MovieFormat> formats = {
      {".mp4", "H.264", "mp4", "libx264", "yuv420p", "crf=16:preset=medium", false, true,
       "plays everywhere (browsers, slides, phones)"},
      {".webm", "VP9", "webm", "libvpx-vp9", "yuv420p",
       "crf=20:b=0:deadline=good:cpu-used=4:row-mt=1", false, true,
       "for web pages; smaller than H.264 at the same quality"},
      {".mkv", "FFV1", "matroska", "ffv1", "bgr0", "level=3:g=1:slicecrc=1", true, false,
       "lossless RGB, any size: for measurement and editing"},
  };
  return formats;
}

std::string movie_formats_markdown() {
  std::string out =
      "| name | codec | FFmpeg encoder | pixels | settings | for |\n"
      "|---|---|---|---|---|---|\n";
  for (const MovieFormat& f : movie_formats())
    out += fmt::format("| `{}` | {}{} | `{}` | {}{} | `{}` | {} |\n", f.extension, f.codec,
                       f.lossless ? " (lossless)" : "", f.encoder, f.pixel_format,
                       f.even_size ? " (even width and height)" : "", f.options, f.use);
  return out;
}

const MovieFormat* find_movie_format(const std::filesystem::path& file) {
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const MovieFormat& f : movie_formats())
    if (f.extension == extension) return &f;
  return nullptr;
}

const MovieFormat& movie_format_for(const std::filesystem::path& file) {
  if (const MovieFormat* f = find_movie_format(file)) return *f;
  std::string choices;
  for (const MovieFormat& f : movie_formats())
    choices += fmt::format("{}{} ({}{})", choices.empty() ? "" : ", ", f.extension, f.codec,
                           f.lossless ? ", lossless" : "");
  throw Error(fmt::format("{}: not a movie name; give {}", file.string(), choices));
}

void check_movie_size(const std::filesystem::path& file, const MovieFormat& format, int width,
                      int height) {
  if (width < 2 || height < 2)
    throw Error(fmt::format("{}: a {}x{} movie is too small; give at least 2x2", file.string(),
                            width, height));
  if (format.even_size && (width % 2 != 0 || height % 2 != 0))
    throw Error(fmt::format(
        "{}: {} ({}) needs an even width and height, not {}x{}; give --width {} --height {}, "
        "or write .mkv (lossless, any size)",
        file.string(), format.codec, format.pixel_format, width, height, width + width % 2,
        height + height % 2));
}

}  // namespace imx
