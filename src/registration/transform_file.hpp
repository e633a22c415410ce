// Linear transforms read from the files registration tools write (ITK / 3D Slicer / ANTs, FSL
// FLIRT, FreeSurfer, AFNI), each in its own convention, as one placement in LPS millimetres.
#pragma once
#include <filesystem>
#include <string>
#include <string_view>

#include <glm/mat4x4.hpp>

namespace imx {

enum class TransformFormat { itk_text, itk_matlab, fsl_flirt, freesurfer_lta, afni_aff12 };

// "ITK text transform", "ITK MATLAB transform", "FSL FLIRT matrix", ...
const char* transform_format_name(TransformFormat format);

// The images a transform file needs beside itself: FSL's matrix is in its images' voxel
// coordinates. Empty paths: not given.
struct TransformFileImages {
  std::filesystem::path moving;     // FLIRT's -in
  std::filesystem::path reference;  // FLIRT's -ref
};

// A registration file's transform as the placement of the registration's moving image in its
// fixed (reference, base, target) image's space: a point of the moving image at p (LPS mm, its
// own world) lies at moving_to_fixed * p in the fixed image's world (LPS mm). Whatever way the
// file stores it (ITK and AFNI store the inverse) is undone by the reader.
struct FileTransform {
  glm::dmat4 moving_to_fixed{1.0};
  TransformFormat format = TransformFormat::itk_text;
};

// The largest transform file read (they are a few hundred bytes): larger is refused unread.
inline constexpr size_t kMaxTransformFileBytes = size_t{1} << 20;

// Reads `file`, choosing the format by its extension and first bytes: .tfm / .txt (ITK text),
// .mat (ITK's MATLAB v4 file, else FSL's text matrix), .lta, .1D. Throws imx::Error (FileError
// when it cannot be read) naming the file and what is wrong: an unknown transform type, a
// truncated file, a non-finite or singular matrix, an FSL matrix without its images.
FileTransform read_transform_file(const std::filesystem::path& file,
                                  const TransformFileImages& images = {});

// The same for a file's bytes already read; `name` gives the extension and names the file in
// messages. FSL matrices still read their images' headers from `images`.
FileTransform parse_transform_file(std::string_view bytes, const std::string& name,
                                   const TransformFileImages& images = {});

}  // namespace imx
