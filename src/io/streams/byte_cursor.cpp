#include "io/streams/byte_cursor.hpp"

#include <cerrno>
#include <fstream>
#include <system_error>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"

namespace imx::detail {

std::string read_file_bytes(const std::filesystem::path& file) {
  require_regular_file(file);
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) throw FileError(fmt::format("{}: cannot read the file size", file.string()), ec.value());
  check_memory(size, file.string());
  std::ifstream in = open_input_stream(file, file.string());
  std::string bytes(static_cast<size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (static_cast<uintmax_t>(in.gcount()) != size)
    throw FileError(fmt::format("{}: cannot read the file", file.string()), errno);
  return bytes;
}

void ByteCursor::need(uint64_t n, std::string_view field) const {
  if (n > remaining())
    throw Error(fmt::format("{}: the file ends inside {} ({} bytes needed at byte {}, {} left)",
                            what_, field, n, pos_, remaining()));
}

std::string_view ByteCursor::line(std::string_view field, size_t limit) {
  const std::string_view rest = bytes_.substr(pos_, std::min(limit + 1, remaining()));
  const size_t eol = rest.find('\n');
  if (eol == std::string_view::npos)
    throw Error(fmt::format("{}: {} is not a line of at most {} bytes", what_, field, limit));
  pos_ += eol + 1;
  return rest.substr(0, eol);
}

}  // namespace imx::detail
