// The format registry's tables of every kind, read together: for listings, the README's table,
// and the kind of a file given on its own.
#include "intermix/formats.hpp"

#include <algorithm>
#include <cerrno>
#include <system_error>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <sys/stat.h>

#include "intermix/error.hpp"
#include "io/mesh/mesh_formats.hpp"
#include "io/overlay/overlay_formats.hpp"
#include "io/streamlines/streamline_formats.hpp"
#include "io/streams/regular_file.hpp"
#include "io/volume/volume_formats.hpp"
#include "labels/label_table_formats.hpp"
#include "registration/transform_formats.hpp"

namespace imx {
namespace {

// Every row's FormatInfo, kind by kind, in each table's order.
std::vector<const detail::FormatInfo*> all_rows() {
  std::vector<const detail::FormatInfo*> rows;
  const auto add = [&rows](const auto& table) {
    for (const auto& row : table) rows.push_back(&row.info);
  };
  add(detail::volume_formats_table());
  add(detail::mesh_formats_table());
  add(detail::overlay_formats_table());
  add(detail::transform_formats_table());
  add(labels_detail::label_table_formats_table());
  add(detail::streamline_formats_table());
  add(detail::connectome_formats_table());
  return rows;
}

std::string rows_of_kind(detail::FileKind kind) {
  std::vector<const detail::FormatInfo*> rows;
  for (const detail::FormatInfo* row : all_rows())
    if (row->kind == kind) rows.push_back(row);
  return detail::list_formats(rows);
}

// The surface an overlay file probably belongs to, for the example in a message: a mesh file
// beside it whose name shares everything before the overlay's last suffix
// (BrainMesh.lh.mz3 for BrainMesh.lh.curv), else lh.pial or rh.pial for FreeSurfer names,
// else "surface.gii".
std::string surface_for_overlay(const std::filesystem::path& file) {
  const std::string name = file.filename().string();
  const size_t dot = name.rfind('.');
  const std::string stem = dot == std::string::npos ? name : name.substr(0, dot + 1);
  std::error_code ec;
  std::vector<std::string> candidates;
  for (const auto& entry : std::filesystem::directory_iterator(
           file.parent_path().empty() ? "." : file.parent_path(), ec)) {
    const std::string other = entry.path().filename().string();
    if (other != name && other.starts_with(stem) && entry.is_regular_file(ec) &&
        detail::find_mesh_format(detail::probe_file(entry.path())) &&
        !detail::find_overlay_format(detail::probe_file(entry.path())))
      candidates.push_back(other);
    if (candidates.size() > 64) break;  // a huge folder: no need to look at all of it
  }
  if (!candidates.empty()) return *std::min_element(candidates.begin(), candidates.end());
  if (name.starts_with("lh.") || name.starts_with("rh.")) return name.substr(0, 3) + "pial";
  return "surface.gii";
}

}  // namespace

std::vector<FileFormat> file_formats() {
  std::vector<FileFormat> out;
  for (const detail::FormatInfo* row : all_rows()) {
    FileFormat f;
    f.kind = detail::file_kind_name(row->kind);
    f.name = row->name;
    for (std::string_view ext : row->extensions) f.extensions.emplace_back(ext);
    f.by_content = row->sniff != nullptr;
    for (std::string_view ext : row->gz_wrapped)
      f.gz_extensions.push_back(fmt::format("{}.gz", ext));
    f.writes = row->writes;
    f.reference = row->reference;
    f.needs = row->needs;
    f.fuzz_target = row->fuzz_target;
    f.fuzz_seeds = row->fuzz_seeds;
    out.push_back(std::move(f));
  }
  return out;
}

std::string file_formats_markdown() {
  std::string out =
      "| kind | format | names | written | checked against | needs |\n"
      "|---|---|---|---|---|---|\n";
  for (const FileFormat& f : file_formats()) {
    std::vector<std::string> names;
    for (const std::string& ext : f.extensions) names.push_back(fmt::format("`{}`", ext));
    for (const std::string& gz : f.gz_extensions) names.push_back(fmt::format("`{}`", gz));
    if (f.by_content) names.push_back("(or by content)");
    out += fmt::format("| {} | {} | {} | {} | {} | {} |\n", f.kind, f.name,
                       names.empty() ? "by content" : fmt::format("{}", fmt::join(names, " ")),
                       f.writes.empty() ? "" : fmt::format("`{}`", f.writes), f.reference, f.needs);
  }
  return out;
}

std::string unknown_format_message(const std::filesystem::path& file) {
  return fmt::format(
      "{}: '{}' is not a format intermix reads; volumes: {}, DICOM folders; meshes: {}; "
      "surface overlays (after their surface): {}; streamlines: {}; connectomes: {}; or a scene "
      "file (.json) alone",
      file.string(), detail::compound_suffix(file), rows_of_kind(detail::FileKind::volume),
      rows_of_kind(detail::FileKind::mesh), rows_of_kind(detail::FileKind::overlay),
      rows_of_kind(detail::FileKind::streamlines), rows_of_kind(detail::FileKind::connectome));
}

IdentifiedFile identify_file(const std::filesystem::path& file) {
  const detail::FileProbe probe = detail::probe_file(file);
  // A FIFO, device or link loop is said as such, not taken for a format by its name alone.
  std::error_code ec;
  if (!probe.folder && std::filesystem::exists(std::filesystem::symlink_status(file, ec)))
    require_regular_file(file);
  const auto found = [](const auto* row) {
    return IdentifiedFile{detail::file_kind_name(row->info.kind), std::string(row->info.name),
                          std::string(row->info.needs)};
  };
  // Overlays first: a GIfTI data file is a .gii, a curvature file has no mesh extension.
  if (const auto* row = detail::find_overlay_format(probe)) return found(row);
  if (const auto* row = detail::find_volume_format(probe)) return found(row);
  // Tractograms before meshes: VTK polydata of lines only is one.
  if (const auto* row = detail::find_streamline_format(probe)) return found(row);
  if (const auto* row = detail::find_connectome_format(probe)) return found(row);
  if (const auto* row = detail::find_mesh_format(probe)) return found(row);
  // Transforms and label tables share ".txt" with every text file: named by it alone, a file is
  // none of them.
  const auto specific = [&probe](const auto* row) {
    return row && ((row->info.sniff && row->info.sniff(probe)) ||
                   detail::matched_extension(row->info, probe.name) != ".txt");
  };
  if (const auto* row = detail::find_format(detail::transform_formats_table(), probe);
      specific(row))
    return found(row);
  if (const auto* row = detail::find_format(labels_detail::label_table_formats_table(), probe);
      specific(row))
    return found(row);
  // A path that is not there (a mistyped DICOM folder has no extension to go by) says so.
  struct stat st {};
  const int err = ::lstat(file.c_str(), &st) == 0 ? 0 : errno;
  if (err == ENOENT) throw FileError(fmt::format("{}: no such file or folder", file.string()), err);
  if (err == ENOTDIR)
    throw FileError(fmt::format("{}: no such file or folder (a file in the path is named as a "
                                "folder)",
                                file.string()),
                    err);
  throw Error(unknown_format_message(file));
}

std::string needs_message(const std::filesystem::path& file, const IdentifiedFile& identified) {
  const std::string name = file.filename().string();
  if (identified.kind == detail::file_kind_name(detail::FileKind::overlay)) {
    return fmt::format(
        "{}: {} is a surface overlay ({}): give it after its surface (intermix render {} {})",
        file.string(), name, identified.format, surface_for_overlay(file), name);
  }
  if (identified.needs.empty())  // read (intermix info) but not drawn: a transform, a label table
    return fmt::format("{}: {} is a {} ({}): intermix reads it but does not draw {}s yet",
                       file.string(), name, identified.kind, identified.format, identified.kind);
  return fmt::format("{}: {} is a {} ({}): it needs {}", file.string(), name, identified.kind,
                     identified.format, identified.needs);
}

}  // namespace imx
