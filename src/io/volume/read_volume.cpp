#include <string>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "io/streams/inflated_file.hpp"
#include "io/streams/regular_file.hpp"
#include "io/volume/volume_formats.hpp"

namespace imx {

namespace {

struct Chosen {
  const detail::VolumeFormat& format;
  bool wrapped;  // a .gz of the format's file: read through an inflated copy
};

// The reader for `file` (a DICOM folder, or a file known by content or name); throws imx::Error
// naming the file and its whole suffix for any other.
Chosen reader_for(const std::filesystem::path& file) {
  const detail::FileProbe probe = detail::probe_file(file);
  if (!probe.folder) require_regular_file(file);
  bool wrapped = false;
  if (const detail::VolumeFormat* format = detail::find_volume_format(probe, &wrapped))
    return {*format, wrapped};
  throw Error(fmt::format("{}: '{}' is not a volume format intermix reads (volumes: {})",
                          file.string(), detail::compound_suffix(file), volume_formats()));
}

// `read(path)` on the file, or on its inflated copy when it is a wrapped .gz.
template <class Read>
auto read_chosen(const Chosen& chosen, const std::filesystem::path& file, Read&& read) {
  if (!chosen.wrapped) return read(file);
  return detail::read_inflated(file, input_limits().max_memory, read);
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
  const Chosen chosen = reader_for(file);
  return read_chosen(chosen, file,
                     [&](const std::filesystem::path& f) { return chosen.format.whole(f, frame); });
}

VolumeHeader read_volume_header(const std::filesystem::path& file) {
  const Chosen chosen = reader_for(file);
  return read_chosen(chosen, file,
                     [&](const std::filesystem::path& f) { return chosen.format.header(f); });
}

VolumeData read_volume_region(const std::filesystem::path& file, const VoxelBox& box, int frame) {
  const Chosen chosen = reader_for(file);
  return read_chosen(chosen, file, [&](const std::filesystem::path& f) {
    return chosen.format.region(f, box, frame);
  });
}

}  // namespace imx
