// GIfTI surfaces (.gii), neuroimaging's mesh format.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "intermix/mesh.hpp"

namespace imx::detail {

// Reads the first POINTSET (vertices) and TRIANGLE data arrays of a GIfTI file
// (read_gifti_arrays checks the whole file), in either index order and any byte order: GIfTI
// coordinates are RAS (NIfTI's), and the caller converts them. The vertices' coordinate systems
// are read: one that maps an anatomical space other than the scanner's (DataSpace
// NIFTI_XFORM_UNKNOWN or _ALIGNED_ANAT, as FreeSurfer writes its tkr-RAS surfaces) to
// NIFTI_XFORM_SCANNER_ANAT (where NIfTI volumes lie) places them by its MatrixData; any other
// (stored coordinates already in the scanner's space, mapped to Talairach or MNI for
// information, as Workbench and nibabel show them) leaves them as stored. Either way, a matrix
// other than the identity is named in a note in `notes`. Triangles naming a vertex that does not
// exist, and a matrix that is not 16 finite numbers of an affine map, are an imx::Error naming
// the file.
Mesh read_gifti(const std::filesystem::path& file, std::vector<std::string>* notes = nullptr);

}  // namespace imx::detail
