// Checks a GIfTI file (.gii) before libgiftiio reads it: the library sizes its buffers from the
// attributes it is given (in int arithmetic), fills missing or undecodable data with zeros
// without failing, and reads whatever file ExternalFileName names.
#pragma once
#include <cstdint>
#include <filesystem>

namespace imx::detail {

// The data arrays of a surface, by their order in the file.
struct GiftiSurfaceArrays {
  int pointset = -1;  // the first NIFTI_INTENT_POINTSET array
  int triangle = -1;  // the first NIFTI_INTENT_TRIANGLE array
};

// Parses the XML (expat) and checks it all before libgiftiio sees it: the elements nest as
// GIfTI's do, no entities, and every data array has a numeric type, 1 to 6 dimensions, a size
// within the memory budget and ASCII, Base64Binary or GZipBase64Binary data in the file
// itself holding exactly the values its dimensions claim (compressed data is inflated to
// count, never past the claim). The first POINTSET and TRIANGLE arrays must be rows of 3,
// floating-point and integer. Throws imx::Error naming the file, the array and the fault.
GiftiSurfaceArrays check_gifti(const std::filesystem::path& file);

}  // namespace imx::detail
