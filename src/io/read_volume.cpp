#include <algorithm>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "intermix/dicom.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/metaimage.hpp"
#include "io/mgh.hpp"
#include "io/nifti.hpp"
#include "io/nrrd.hpp"
#include "io/regular_file.hpp"

namespace imx {

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The formats read_volume knows by extension, each with its three ways to be read.
struct Reader {
  VolumeData (*whole)(const std::filesystem::path&, int frame);
  VolumeHeader (*header)(const std::filesystem::path&);
  VolumeData (*region)(const std::filesystem::path&, const VoxelBox&, int frame);
};

constexpr const char* kVolumeFormats =
    ".nrrd, .nhdr, .nii, .nii.gz, .hdr/.img (NIfTI or Analyze 7.5 pairs, also .gz), .mha, .mhd, "
    ".mgh, .mgz, DICOM";

// The reader for a file's name (lower case), if any.
std::optional<Reader> reader_by_name(std::string name) {
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ends_with(name, ".nrrd") || ends_with(name, ".nhdr"))
    return Reader{detail::read_nrrd, detail::read_nrrd_header, detail::read_nrrd_region};
  // NIfTI-1/2 single files, and .hdr/.img pairs (NIfTI-1/2 or Analyze 7.5) named by either.
  if (ends_with(name, ".nii") || ends_with(name, ".nii.gz") || ends_with(name, ".hdr") ||
      ends_with(name, ".hdr.gz") || ends_with(name, ".img") || ends_with(name, ".img.gz"))
    return Reader{detail::read_nifti, detail::read_nifti_header, detail::read_nifti_region};
  if (ends_with(name, ".mha") || ends_with(name, ".mhd"))
    return Reader{detail::read_metaimage, detail::read_metaimage_header,
                  detail::read_metaimage_region};
  if (ends_with(name, ".mgh") || ends_with(name, ".mgz") || ends_with(name, ".mgh.gz"))
    return Reader{detail::read_mgh, detail::read_mgh_header, detail::read_mgh_region};
  return std::nullopt;
}

// The reader for `file`'s extension; throws imx::Error naming the file for any other.
Reader reader_for(const std::filesystem::path& file) {
  require_regular_file(file);
  if (std::optional<Reader> r = reader_by_name(file.filename().string())) return *r;
  throw Error(fmt::format("{}: unknown volume format '{}' (supported: {})", file.string(),
                          file.extension().string(), kVolumeFormats));
}

}  // namespace

bool is_volume_file(const std::filesystem::path& file) {
  return reader_by_name(file.filename().string()).has_value() || is_dicom_source(file);
}

std::string volume_formats() {
  return kVolumeFormats;
}

VolumeData read_volume(const std::filesystem::path& file, int frame) {
  // A folder, a DICOMDIR or a DICOM file: the largest image series (read_dicom chooses).
  if (is_dicom_source(file)) {
    DicomReadOptions options;
    options.frame = frame;
    return read_dicom(file, options).volume;
  }
  return reader_for(file).whole(file, frame);
}

VolumeHeader read_volume_header(const std::filesystem::path& file) {
  // A DICOM series' placement comes from all its slices (their order, spacing and tilt), so
  // the series is read whole.
  if (is_dicom_source(file)) return read_dicom_header(file);
  return reader_for(file).header(file);
}

VolumeData read_volume_region(const std::filesystem::path& file, const VoxelBox& box, int frame) {
  // DICOM is read whole and cropped: its voxels come slice file by slice file, decoded (and
  // possibly decompressed) by GDCM, with no byte layout to seek in.
  if (is_dicom_source(file)) return crop(read_volume(file, frame), box, file.string());
  return reader_for(file).region(file, box, frame);
}

}  // namespace imx
