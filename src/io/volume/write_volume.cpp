// write_volume: the writer a file's extension names.
#include <optional>
#include <string>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/streams/header_text.hpp"

namespace imx {

namespace {

enum class VolumeFormat { nifti_gz, nifti, nrrd, metaimage };

std::optional<VolumeFormat> format_of(const std::filesystem::path& file) {
  const std::string name = detail::lower(file.filename().string());
  auto ends_with = [&](const std::string& suffix) {
    return name.size() > suffix.size() &&
           name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  if (ends_with(".nii.gz")) return VolumeFormat::nifti_gz;
  if (ends_with(".nii")) return VolumeFormat::nifti;
  if (ends_with(".nrrd")) return VolumeFormat::nrrd;
  if (ends_with(".mha")) return VolumeFormat::metaimage;
  return std::nullopt;
}

}  // namespace

bool can_write_volume(const std::filesystem::path& file) {
  return format_of(file).has_value();
}

void write_volume(const VolumeData& volume, const std::filesystem::path& file, bool compress) {
  std::optional<VolumeFormat> format = format_of(file);
  if (!format)
    throw Error(
        fmt::format("{}: cannot write volumes of this type (write .nii.gz, .nii, .nrrd or "
                    ".mha)",
                    file.string()));
  switch (*format) {
    case VolumeFormat::nifti_gz:
      return write_nifti(volume, file, true);
    case VolumeFormat::nifti:
      return write_nifti(volume, file, false);
    case VolumeFormat::nrrd:
      return write_nrrd(volume, file, compress);
    case VolumeFormat::metaimage:
      return write_metaimage(volume, file, compress);
  }
}

}  // namespace imx
