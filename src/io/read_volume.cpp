#include <algorithm>
#include <string>

#include <fmt/format.h>

#include "intermix/dicom.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/metaimage.hpp"
#include "io/nifti.hpp"
#include "io/nrrd.hpp"
#include "io/regular_file.hpp"

namespace imx {

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

VolumeData read_volume(const std::filesystem::path& file) {
  const std::string what = file.string();
  // A folder, a DICOMDIR or a DICOM file: the largest image series (read_dicom chooses).
  if (is_dicom_source(file)) return read_dicom(file).volume;
  require_regular_file(file);

  std::string name = file.filename().string();
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ends_with(name, ".nrrd") || ends_with(name, ".nhdr")) return detail::read_nrrd(file);
  if (ends_with(name, ".nii") || ends_with(name, ".nii.gz")) return detail::read_nifti(file);
  if (ends_with(name, ".mha") || ends_with(name, ".mhd")) return detail::read_metaimage(file);
  throw Error(
      fmt::format("{}: unknown volume format '{}' (supported: .nrrd, .nhdr, .nii, .nii.gz, .mha, "
                  ".mhd, DICOM)",
                  what, file.extension().string()));
}

}  // namespace imx
