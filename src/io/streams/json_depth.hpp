// The nesting depth of JSON text, checked before nlohmann parses it recursively: a deep nest
// would exhaust the stack and costs far more memory per byte than a flat document.
#pragma once
#include <cstddef>
#include <string_view>

namespace imx::detail {

// Whether `text` nests arrays and objects deeper than `max_depth` (brackets inside strings not
// counted).
inline bool json_nested_deeper_than(std::string_view text, int max_depth) {
  int depth = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) return true;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return false;
}

}  // namespace imx::detail
