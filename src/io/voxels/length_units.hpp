// Units of length in the files' metadata (OME-Zarr axes, OME-TIFF physical sizes, ImageJ
// calibrations), converted to the millimetres of world space.
#pragma once
#include <optional>
#include <string_view>

namespace imx::detail {

// Millimetres in one `unit`: NGFF's names ("micrometer"), OME's symbols ("µm", "Å") and
// ImageJ's spellings ("micron", "um"); nullopt for any other unit (a caller names it).
std::optional<double> millimetres_per_unit(std::string_view unit);

// "angstrom, nanometer, ..., foot": the units read, for messages.
const char* length_units_read();

}  // namespace imx::detail
