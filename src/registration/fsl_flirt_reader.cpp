// FSL FLIRT's matrices (-omat): a 4x4 text matrix from the input (moving) image's scaled-voxel
// coordinates to the reference image's. Scaled voxels are voxel indices times pixdim, with the
// first index flipped (nx - 1 - i) when the image's sform (else qform) has a positive
// determinant ("neurological" storage), FSL's own rule; with neither, FSL takes the image as
// radiological and flips nothing.
#include <cmath>

#include <cctype>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"
#include "io/streams/file_head.hpp"
#include "io/voxels/nifti_header.hpp"
#include "registration/transform_readers.hpp"

namespace imx::detail {
namespace {

bool ends_with(const std::string& s, std::string_view suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The image's index-to-world (LPS, as intermix places it) and index-to-scaled-voxel matrices.
struct FslImage {
  glm::dmat4 index_to_world;
  glm::dmat4 index_to_scaled;
};

FslImage fsl_image(const std::filesystem::path& file, const std::string& role,
                   const std::string& what) {
  std::string low = file.filename().string();
  for (char& c : low) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const bool pair = ends_with(low, ".hdr") || ends_with(low, ".hdr.gz");
  if (!pair && !ends_with(low, ".nii") && !ends_with(low, ".nii.gz"))
    throw Error(
        fmt::format("{}: the {} image {} is not NIfTI (.nii, .nii.gz or .hdr): FSL's "
                    "matrices are in NIfTI images' voxel coordinates",
                    what, role, file.string()));
  const std::string image_what = fmt::format("{} ({} image of {})", file.string(), role, what);
  const FileHead head = read_file_head(file, 540, image_what);
  const NiftiHeader h = decode_nifti_header(head.bytes, pair, head.gzipped, image_what);
  const glm::dmat4 world = nifti_index_to_world(h);
  glm::dmat4 scaled(1.0);
  for (int a = 0; a < 3; ++a) {
    const double d = std::abs(h.pixdim[static_cast<size_t>(a + 1)]);
    if (!(d > 0.0) || !std::isfinite(d))
      throw Error(fmt::format("{}: pixdim[{}] is {}; FSL's scaled voxels need a voxel size > 0",
                              image_what, a + 1, h.pixdim[static_cast<size_t>(a + 1)]));
    scaled[a][a] = d;
  }
  const bool has_placement = h.sform_code > 0 || h.qform_code > 0;
  if (has_placement && glm::determinant(glm::dmat3(world)) > 0.0) {
    // x_scaled = (nx - 1 - i) * dx
    scaled[0][0] = -scaled[0][0];
    scaled[3][0] = static_cast<double>(h.dim[1] - 1) * std::abs(h.pixdim[1]);
  }
  return {world, scaled};
}

}  // namespace

glm::dmat4 read_fsl_matrix(std::string_view text, const std::string& what) {
  std::vector<double> values;
  for (std::string_view line : text_lines(text, what))
    for (std::string_view w : words(line)) {
      if (values.size() == 16)
        throw Error(fmt::format("{}: more than 16 numbers; an FSL matrix is 4 rows of 4", what));
      values.push_back(parse_number(w, what, fmt::format("entry {}", values.size() + 1)));
    }
  if (values.size() != 16)
    throw Error(fmt::format("{}: {} numbers; an FSL matrix is 4 rows of 4 (truncated?)", what,
                            values.size()));
  const double last[4] = {0.0, 0.0, 0.0, 1.0};
  for (int c = 0; c < 4; ++c)
    if (std::abs(values[static_cast<size_t>(12 + c)] - last[c]) > 1e-6)
      throw Error(fmt::format("{}: the last row must be 0 0 0 1 (an affine matrix)", what));
  double rows[3][4];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) rows[r][c] = values[static_cast<size_t>(4 * r + c)];
  return affine_from_rows(rows);
}

glm::dmat4 fsl_world_matrix(const glm::dmat4& flirt, const std::filesystem::path& moving,
                            const std::filesystem::path& reference, const std::string& what) {
  if (moving.empty() || reference.empty())
    throw Error(fmt::format(
        "{}: an FSL FLIRT matrix is in its images' voxel coordinates: name the images it was "
        "computed with in the transform, \"moving\" (FLIRT's -in) and \"reference\" (-ref){}",
        what,
        moving.empty() && reference.empty() ? ""
        : moving.empty()                    ? " (\"moving\" is missing)"
                                            : " (\"reference\" is missing)"));
  const FslImage in = fsl_image(moving, "moving", what);
  const FslImage ref = fsl_image(reference, "reference", what);
  // moving world -> moving index -> moving scaled -> reference scaled -> reference world.
  return ref.index_to_world * glm::inverse(ref.index_to_scaled) * flirt * in.index_to_scaled *
         glm::inverse(in.index_to_world);
}

}  // namespace imx::detail
