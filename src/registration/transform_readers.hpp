// The readers behind read_transform_file, one per format, on a file's bytes. Each returns the
// matrix the file stores, in the direction and space the file stores it; transform_file.cpp
// turns it into the moving image's placement. `what` names the file in messages.
#pragma once
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <glm/mat4x4.hpp>

namespace imx::detail {

// One ITK transform as its files store it: the class name ("AffineTransform_double_3_3"),
// Parameters and FixedParameters.
struct ItkTransform {
  std::string type;
  std::vector<double> parameters;
  std::vector<double> fixed;
};

// ITK's map of a transform: fixed-space points (LPS mm) to moving-space points, by ITK's
// definitions: T(x) = A (x - c) + c + t with the centre c from the fixed parameters.
// Affine / MatrixOffsetTransformBase / Rigid3D (9 matrix entries row by row, then t),
// Euler3D (angles x, y, z in radians, then t; A = Rz Rx Ry, or Rz Ry Rx when the fourth fixed
// parameter, ComputeZYX, is non-zero), VersorRigid3D (the versor's vector part, then t),
// Similarity3D (versor, t, then the scale s: A = s R), Translation (t), Identity. Throws for
// another type or a parameter count that does not match it.
glm::dmat4 itk_fixed_to_moving(const ItkTransform& transform, const std::string& what);

// An "#Insight Transform File V1.0" text: one transform, or a CompositeTransform of linear
// ones (applied last first, as ITK does). ITK's map, fixed to moving.
glm::dmat4 read_itk_text(std::string_view text, const std::string& what);

// True when `bytes` start like a MATLAB v4 file as ITK's MatlabTransformIO writes it (a numeric
// variable header whose name follows it), not like text.
bool looks_like_matlab_v4(std::string_view bytes);
// ITK's MatlabTransformIO file: two MATLAB v4 column vectors, the parameters (named by the
// transform type) and "fixed". ITK's map, fixed to moving.
glm::dmat4 read_itk_matlab(std::string_view bytes, const std::string& what);

// FSL FLIRT's 4x4 text matrix: input (moving) to reference, in their scaled-voxel coordinates.
glm::dmat4 read_fsl_matrix(std::string_view text, const std::string& what);
// FLIRT's matrix as a map of world points, moving image LPS to reference image LPS, from the
// two images' NIfTI headers (FSL's scaled voxels: index times pixdim, the first index flipped
// when the sform's, else the qform's, determinant is positive).
glm::dmat4 fsl_world_matrix(const glm::dmat4& flirt, const std::filesystem::path& moving,
                            const std::filesystem::path& reference, const std::string& what);

// A FreeSurfer .lta of one LINEAR_VOX_TO_VOX or LINEAR_RAS_TO_RAS transform: source to
// destination, as a map of LPS points (voxel matrices go through the file's volume geometry).
glm::dmat4 read_lta(std::string_view text, const std::string& what);

// AFNI's .aff12.1D (3dAllineate / 3dvolreg -1Dmatrix_save): one row of 12 numbers, or three
// rows of 4: the base-to-source map in DICOM-order (LPS) coordinates.
glm::dmat4 read_afni_aff12(std::string_view text, const std::string& what);

// Shared text handling.
std::vector<std::string_view> text_lines(std::string_view text, const std::string& what);
std::vector<std::string_view> words(std::string_view line);
// `token` as a finite double; throws "what: field: ..." otherwise.
double parse_number(std::string_view token, const std::string& what, std::string_view field);
// The 3x3 part as a row-major list and t: a 4x4 whose last row is 0 0 0 1.
glm::dmat4 affine_from_rows(const double (&rows)[3][4]);

}  // namespace imx::detail
