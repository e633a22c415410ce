// The header of a NIfTI-1, NIfTI-2 or Analyze 7.5 image, decoded and checked: the fields the
// NIfTI reader uses, in host byte order and as doubles, whichever of the three wrote them.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include <glm/mat4x4.hpp>

#include "io/voxels/raw_voxels.hpp"

namespace imx::detail {

enum class NiftiKind { nifti1, nifti2, analyze };

// "NIfTI-1", "NIfTI-2", "Analyze 7.5".
const char* nifti_kind_name(NiftiKind kind);

struct NiftiHeader {
  NiftiKind kind = NiftiKind::nifti1;
  bool single_file = true;       // magic n+1 / n+2: the voxels follow the header in the same file
  bool swapped = false;          // the file's byte order is not the host's (for header and voxels)
  int ndim = 3;                  // dim[0]
  std::array<int64_t, 8> dim{};  // dim[1..ndim], positive; 1 beyond ndim
  std::array<double, 8> pixdim{};  // as stored
  int datatype = 0;
  RawType type = RawType::u8;
  // RGB24 (3) or RGBA32 (4): a colour image, that many interleaved uint8 channels per voxel
  // (`type` u8); 0 for a scalar image.
  int colour_channels = 0;
  uint64_t vox_offset = 0;  // where the voxels start in their file
  // Intensity scaling, value * slope + inter, already decided by the rules of the header's kind
  // (NIfTI's scl_slope/scl_inter; SPM2's for Analyze); slope 0 means none.
  double slope = 0.0, inter = 0.0;
  int qform_code = 0, sform_code = 0;  // NIfTI only
  double quatern_b = 0.0, quatern_c = 0.0, quatern_d = 0.0;
  std::array<double, 3> qoffset{};
  std::array<std::array<double, 4>, 3> srow{};
  int xyzt_units = 0;                   // NIfTI only
  int intent_code = 0;                  // NIfTI only (CIFTI-2 files: 3000-3099)
  std::array<int16_t, 3> spm_origin{};  // Analyze only: SPM's "originator" voxel, 1-based
};

// Decodes a header from the first bytes of its file (`head`: at least 348 bytes for NIfTI-1 and
// Analyze, 540 for NIfTI-2; more are ignored). `pair`: the file is the .hdr of a .hdr/.img pair,
// whose magic must be "ni1" or "ni2" or absent (Analyze 7.5); else it is a single .nii file,
// whose magic must be "n+1" or "n+2". A bad magic is refused, never read as Analyze (which
// nifticlib does, dropping the sform). `gzipped` only words the message for a short header.
// Throws imx::Error naming `what` and the field at fault.
NiftiHeader decode_nifti_header(std::string_view head, bool pair, bool gzipped,
                                const std::string& what);

// The header's index-to-world transform in LPS: the sform, else the qform, else pixdim scaling
// (NIfTI's "method 1"); for Analyze, the affine nibabel gives it (see the definition).
glm::dmat4 nifti_index_to_world(const NiftiHeader& h);

// "WHAT is a CIFTI-2 file of surface data: give it after its surfaces (...)": what the NIfTI
// reader says of one (intent codes 3000-3099), and a scene of such a file without surfaces.
std::string cifti_needs_surfaces(const std::string& what);

}  // namespace imx::detail
