#include "presets/text_file.hpp"

#include <cerrno>
#include <fstream>
#include <sstream>
#include <system_error>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"

namespace imx {

std::string read_text_file(const std::filesystem::path& file, size_t max_bytes) {
  require_regular_file(file);
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) throw Error(fmt::format("{}: cannot read its size: {}", file.string(), ec.message()));
  if (size > max_bytes)
    throw Error(fmt::format("{}: {} bytes is more than the {} this kind of file may have",
                            file.string(), size, max_bytes));
  std::ifstream in = open_input_stream(file, file.string());
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error(fmt::format("{}: reading failed", file.string()));
  return text.str();
}

}  // namespace imx
