// How preset names are compared: the scene spelling "ct-bone" and Slicer's "CT-Bone" are one.
#pragma once
#include <string>
#include <string_view>

namespace imx {

// `name` in lower case with '_' and ' ' turned into '-'.
std::string preset_key(std::string_view name);

}  // namespace imx
