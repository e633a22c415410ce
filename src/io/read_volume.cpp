#include <string>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/regular_file.hpp"
#include "io/volume_formats.hpp"

namespace imx {

namespace {

// The reader for `file` (a DICOM folder, or a file known by content or name); throws imx::Error
// naming the file and its whole suffix for any other.
const detail::VolumeFormat& reader_for(const std::filesystem::path& file) {
  const detail::FileProbe probe = detail::probe_file(file);
  if (!probe.folder) require_regular_file(file);
  if (const detail::VolumeFormat* format = detail::find_volume_format(probe)) return *format;
  throw Error(fmt::format("{}: '{}' is not a volume format intermix reads (volumes: {})",
                          file.string(), detail::compound_suffix(file), volume_formats()));
}

}  // namespace

bool is_volume_file(const std::filesystem::path& file) {
  return detail::find_volume_format(detail::probe_file(file)) != nullptr;
}

std::string volume_formats() {
  std::vector<const detail::FormatInfo*> rows;
  for (const detail::VolumeFormat& format : detail::volume_formats_table())
    rows.push_back(&format.info);
  return detail::list_formats(rows) + ", DICOM folders";
}

VolumeData read_volume(const std::filesystem::path& file, int frame) {
  return reader_for(file).whole(file, frame);
}

VolumeHeader read_volume_header(const std::filesystem::path& file) {
  return reader_for(file).header(file);
}

VolumeData read_volume_region(const std::filesystem::path& file, const VoxelBox& box, int frame) {
  return reader_for(file).region(file, box, frame);
}

}  // namespace imx
