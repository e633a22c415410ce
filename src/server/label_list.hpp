// The labels a label volume holds, for the viewer's object list: which values occur in its voxels
// and how its map draws each (name, colour, opacity, visibility).
#pragma once
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "intermix/labels.hpp"
#include "intermix/volume.hpp"

namespace imx::server {

// The most labels the viewer lists for one volume (FreeSurfer's aseg has about 45, a parcellation
// a few hundred); the lowest values are kept.
inline constexpr size_t kMaxListedLabels = 1024;

// The distinct integer values of `data`'s voxels, ascending, at most kMaxListedLabels (NaN and
// non-integers skipped: a label volume holds none).
std::vector<int32_t> present_labels(const VolumeData& data);

// [{value, name, color, opacity, visible}, ...] for `values` as `map` draws them.
nlohmann::json label_list_json(const LabelMap& map, const std::vector<int32_t>& values);

}  // namespace imx::server
