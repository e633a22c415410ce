// Which values a label volume's voxels hold: what the viewer lists and a legend names.
#pragma once
#include <cstdint>
#include <vector>

#include "intermix/volume.hpp"

namespace imx {

// The most labels listed for one volume (FreeSurfer's aseg has about 45, a parcellation a few
// hundred); the lowest values are kept.
inline constexpr size_t kMaxListedLabels = 1024;

// The distinct integer values of `data`'s voxels, ascending, at most kMaxListedLabels (NaN and
// non-integers skipped: a label volume holds none).
std::vector<int32_t> present_labels(const VolumeData& data);

}  // namespace imx
