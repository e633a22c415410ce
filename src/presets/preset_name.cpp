#include "presets/preset_name.hpp"

namespace imx {

std::string preset_key(std::string_view name) {
  std::string key(name);
  for (char& c : key) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    if (c == '_' || c == ' ') c = '-';
  }
  return key;
}

}  // namespace imx
