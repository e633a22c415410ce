#include "io/streams/regular_file.hpp"

#include <cerrno>
#include <system_error>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streams/input_file.hpp"

namespace imx {
namespace {

const char* kind_of(std::filesystem::file_type type) {
  switch (type) {
    case std::filesystem::file_type::directory:
      return "is a directory, not a file";
    case std::filesystem::file_type::fifo:
      return "is a FIFO (named pipe), not a regular file";
    case std::filesystem::file_type::character:
      return "is a character device, not a regular file";
    case std::filesystem::file_type::block:
      return "is a block device, not a regular file";
    case std::filesystem::file_type::socket:
      return "is a socket, not a regular file";
    default:
      return "is not a regular file";
  }
}

// The file's type with symbolic links followed; throws for a link loop or an unreadable path.
std::filesystem::file_type type_of(const std::filesystem::path& file, const std::string& what) {
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(file, ec);
  if (ec == std::errc::too_many_symbolic_link_levels)
    throw FileError(fmt::format("{}: symbolic link loop (too many levels of links)", what), ELOOP);
  if (ec && st.type() != std::filesystem::file_type::not_found)
    throw FileError(fmt::format("{}: cannot look at the file: {}", what, ec.message()), ec.value());
  return st.type();
}

}  // namespace

void require_regular_file(const std::filesystem::path& file, const std::string& what) {
  open_input(file, what);  // the guarded open: checked on the descriptor, never blocking
}

std::filesystem::path resolve_data_file(const std::filesystem::path& header,
                                        const std::string& name, const std::string& reference) {
  std::filesystem::path data = name;
  const std::filesystem::path folder = header.parent_path();
  if (data.is_relative()) data = folder / data;
  const std::string what = fmt::format("{} (data file of {})", data.string(), header.string());
  if (!input_limits().allow_external_data) {
    std::error_code folder_ec, ec;  // either failing refuses the file
    const auto inside = std::filesystem::weakly_canonical(folder.empty() ? "." : folder, folder_ec);
    const auto target = std::filesystem::weakly_canonical(data, ec);
    if (folder_ec) ec = folder_ec;
    if (ec) {
      if (ec == std::errc::too_many_symbolic_link_levels)
        throw FileError(fmt::format("{}: {} names {}, which cannot be resolved: a symbolic link "
                                    "loop (too many levels of links)",
                                    header.string(), reference, data.string()),
                        ELOOP);
      throw FileError(fmt::format("{}: {} names {}, which cannot be resolved: {}", header.string(),
                                  reference, data.string(), ec.message()),
                      ec.value());
    }
    const auto relative = target.lexically_relative(inside);
    if (relative.empty() || *relative.begin() == "..")
      throw Error(
          fmt::format("{}: {} names {}, outside the file's folder; pass "
                      "--allow-external-data to read it",
                      header.string(), reference, target.string()));
  }
  require_regular_file(data, what);
  return data;
}

void require_regular_or_new_file(const std::filesystem::path& file) {
  const std::filesystem::file_type type = type_of(file, file.string());
  if (type != std::filesystem::file_type::not_found && type != std::filesystem::file_type::regular)
    throw FileError(
        fmt::format("{}: {}; only regular files are written", file.string(), kind_of(type)),
        type == std::filesystem::file_type::directory ? EISDIR : 0);
}

}  // namespace imx
