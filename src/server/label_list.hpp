// The labels a label volume holds, for the viewer's object list: how its map draws each value
// its voxels hold (labels/present_labels.hpp): name, colour, opacity, visibility.
#pragma once
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "intermix/labels.hpp"
#include "intermix/volume.hpp"
#include "labels/present_labels.hpp"

namespace imx::server {

// [{value, name, color, opacity, visible}, ...] for `values` as `map` draws them.
nlohmann::json label_list_json(const LabelMap& map, const std::vector<int32_t>& values);

}  // namespace imx::server
