#include "io/registry/format_registry.hpp"

#include <algorithm>
#include <exception>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "intermix/error.hpp"
#include "io/streams/file_head.hpp"
#include "io/streams/gzip.hpp"
#include "io/streams/header_text.hpp"

namespace imx::detail {

const char* file_kind_name(FileKind kind) {
  switch (kind) {
    case FileKind::volume:
      return "volume";
    case FileKind::mesh:
      return "mesh";
    case FileKind::overlay:
      return "surface overlay";
    case FileKind::transform:
      return "transform";
    case FileKind::label_table:
      return "label table";
    case FileKind::streamlines:
      return "streamlines";
    case FileKind::connectome:
      return "connectome";
  }
  return "file";
}

FileProbe probe_name(const std::filesystem::path& file) {
  FileProbe probe;
  probe.path = file;
  probe.name = lower(file.filename().string());
  return probe;
}

FileProbe probe_file(const std::filesystem::path& file) {
  FileProbe probe = probe_name(file);
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(file, ec);
  probe.folder = !ec && std::filesystem::is_directory(status);
  // Only regular files are opened: a FIFO would block (the reader refuses it by name).
  if (ec || !std::filesystem::is_regular_file(status)) return probe;
  try {
    probe.head = read_file_head(file, kProbeBytes, file.string()).bytes;
  } catch (const Error&) {
    // Corrupt gzip data or no permission: the format is then known by name and its reader
    // says what is wrong.
  }
  return probe;
}

std::string_view matched_extension(const FormatInfo& row, std::string_view name) {
  std::string_view best;
  for (std::string_view ext : row.extensions)
    if (ext.size() > best.size() && name.size() > ext.size() && name.ends_with(ext)) best = ext;
  return best;
}

std::string compound_suffix(const std::filesystem::path& file) {
  const std::string name = lower(file.filename().string());
  const size_t last = name.rfind('.');
  if (last == std::string::npos || last == 0) return name;
  static constexpr std::string_view kCompressions[] = {".gz", ".bz2", ".xz", ".zst", ".zip"};
  const std::string_view ext = std::string_view(name).substr(last);
  if (std::find(std::begin(kCompressions), std::end(kCompressions), ext) == std::end(kCompressions))
    return std::string(ext);
  const size_t before = name.rfind('.', last - 1);
  return before == std::string::npos || before == 0 ? std::string(ext) : name.substr(before);
}

std::string list_formats(std::span<const FormatInfo* const> rows) {
  std::vector<std::string> items;
  for (const FormatInfo* row : rows) {
    std::vector<std::string> names(row->extensions.begin(), row->extensions.end());
    for (std::string_view ext : row->gz_wrapped) names.push_back(fmt::format("{}.gz", ext));
    items.push_back(names.empty() ? fmt::format("{} (by content)", row->name)
                                  : fmt::format("{} ({})", row->name, fmt::join(names, " ")));
  }
  return fmt::format("{}", fmt::join(items, ", "));
}

}  // namespace imx::detail
