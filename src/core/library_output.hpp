// What third-party libraries print (libjpeg's "Corrupt JPEG data", OpenJPEG's and GDCM's
// messages), captured instead of mixed into intermix's own output: kept here for `--verbose`,
// which prints it after intermix's own line.
#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace imx::detail {

// Keeps `text` (one or more lines) that the library `from` printed while reading `what`. At
// most the last 200 lines are kept. Thread-safe.
void keep_library_output(std::string_view from, std::string_view what, std::string_view text);

// The lines kept so far, as "FROM (WHAT): LINE", oldest first; clears them.
std::vector<std::string> take_library_output();

}  // namespace imx::detail
