// The attributes of an AFNI .HEAD file ("type = ...-attribute", "name = ...", "count = ...",
// then the value), parsed as nibabel.brikhead parses them, with hard bounds on every count.
#pragma once
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace imx::detail {

struct AfniAttribute {
  enum class Kind { string, integer, floating };
  Kind kind = Kind::string;
  std::string text;             // string attributes: the value without its quote and '~' ends
  std::vector<double> numbers;  // integer and float attributes: exactly `count` values
};

// name -> attribute; a name given twice keeps its last value, as nibabel's dict does.
using AfniAttributes = std::map<std::string, AfniAttribute, std::less<>>;

// The attributes of the HEAD text `head`. Attributes are separated by a blank line; each starts
// with its type, name and count lines. Throws imx::Error naming `what` and the attribute when
// one is malformed or its count disagrees with its value.
AfniAttributes parse_afni_attributes(std::string_view head, const std::string& what);

}  // namespace imx::detail
