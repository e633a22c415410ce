// read_transform_file: the format by extension and content, and each format's direction
// turned into the moving image's placement in the fixed image's space.
#include "registration/transform_file.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "core/math.hpp"
#include "intermix/error.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"
#include "registration/transform_formats.hpp"
#include "registration/transform_readers.hpp"

namespace imx {
namespace {

TransformFormat detect_format(std::string_view bytes, const std::string& name) {
  detail::FileProbe probe = detail::probe_name(name);
  probe.head = bytes.substr(0, detail::kProbeBytes);
  if (const auto* row = detail::find_format(detail::transform_formats_table(), probe))
    return row->format;
  std::vector<const detail::FormatInfo*> rows;
  for (const detail::TransformFileFormat& row : detail::transform_formats_table())
    rows.push_back(&row.info);
  throw Error(fmt::format("{}: '{}' is not a transform format intermix reads (transforms: {})",
                          name, detail::compound_suffix(name), detail::list_formats(rows)));
}

// Throws unless `m` is finite, affine and invertible (relative to its own scale).
void check_invertible(const glm::dmat4& m, const std::string& what) {
  if (!all_finite(m))
    throw Error(fmt::format("{}: the transform has a non-finite entry (NaN or infinity)", what));
  const glm::dmat3 a(m);
  const double norm = glm::length(a[0]) * glm::length(a[1]) * glm::length(a[2]);
  const double det = glm::determinant(a);
  if (!(norm > 0.0) || std::abs(det) <= 1e-9 * norm)
    throw Error(
        fmt::format("{}: the transform is singular (determinant {:g}): it flattens space "
                    "and places no image",
                    what, det));
}

}  // namespace

const char* transform_format_name(TransformFormat format) {
  switch (format) {
    case TransformFormat::itk_text:
      return "ITK text transform";
    case TransformFormat::itk_matlab:
      return "ITK binary (MATLAB v4) transform";
    case TransformFormat::fsl_flirt:
      return "FSL FLIRT matrix";
    case TransformFormat::freesurfer_lta:
      return "FreeSurfer LTA";
    case TransformFormat::afni_aff12:
      return "AFNI aff12 matrix";
  }
  return "transform";
}

FileTransform parse_transform_file(std::string_view bytes, const std::string& name,
                                   const TransformFileImages& images) {
  if (bytes.size() > kMaxTransformFileBytes)
    throw Error(fmt::format("{}: {} bytes; a linear transform file is at most {} bytes", name,
                            bytes.size(), kMaxTransformFileBytes));
  if (bytes.empty()) throw Error(fmt::format("{}: the file is empty", name));
  FileTransform out;
  out.format = detect_format(bytes, name);
  if (out.format != TransformFormat::fsl_flirt &&
      (!images.moving.empty() || !images.reference.empty()))
    throw Error(
        fmt::format("{}: is an {}, which needs no images: \"moving\" and \"reference\" "
                    "are for FSL FLIRT matrices",
                    name, transform_format_name(out.format)));
  glm::dmat4 stored(1.0);
  switch (out.format) {
    case TransformFormat::itk_text:
      stored = detail::read_itk_text(bytes, name);
      break;
    case TransformFormat::itk_matlab:
      stored = detail::read_itk_matlab(bytes, name);
      break;
    case TransformFormat::fsl_flirt:
      stored = detail::read_fsl_matrix(bytes, name);
      check_invertible(stored, name);
      stored = detail::fsl_world_matrix(stored, images.moving, images.reference, name);
      break;
    case TransformFormat::freesurfer_lta:
      stored = detail::read_lta(bytes, name);
      break;
    case TransformFormat::afni_aff12:
      stored = detail::read_afni_aff12(bytes, name);
      break;
  }
  check_invertible(stored, name);
  // ITK and AFNI store the resampling direction, fixed (base) to moving (source).
  const bool fixed_to_moving = out.format == TransformFormat::itk_text ||
                               out.format == TransformFormat::itk_matlab ||
                               out.format == TransformFormat::afni_aff12;
  out.moving_to_fixed = fixed_to_moving ? glm::inverse(stored) : stored;
  check_invertible(out.moving_to_fixed, name);
  return out;
}

FileTransform read_transform_file(const std::filesystem::path& file,
                                  const TransformFileImages& images) {
  const std::string what = file.string();
  require_regular_file(file);
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(file, ec);
  if (!ec && size > kMaxTransformFileBytes)
    throw Error(fmt::format("{}: {} bytes; a linear transform file is at most {} bytes", what, size,
                            kMaxTransformFileBytes));
  std::ifstream in = open_input_stream(file, what);
  std::string bytes(kMaxTransformFileBytes + 1, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  bytes.resize(static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return parse_transform_file(bytes, what, images);
}

}  // namespace imx
