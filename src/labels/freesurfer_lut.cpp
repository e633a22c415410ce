// FreeSurfer's colour LUT text: `No. Name R G B A` per row, A the transparency.
#include <fmt/format.h>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "labels/colour_table_readers.hpp"
#include "labels/label_text.hpp"

namespace imx::labels_detail {

std::vector<LabelEntry> parse_freesurfer_lut(std::string_view text, const std::string& what) {
  std::vector<LabelEntry> entries;
  const std::vector<std::string_view> rows = lines(text);
  for (size_t n = 0; n < rows.size(); ++n) {
    if (skippable(rows[n])) continue;
    const auto t = tokens(rows[n]);
    const std::string where = fmt::format("{}: line {}", what, n + 1);
    if (t.size() != 6)
      throw Error(fmt::format("{}: {} fields; a FreeSurfer LUT row is 'No. Name R G B A'", where,
                              t.size()));
    int64_t value = 0;
    if (!parse_int(t[0], value) || value < -kMaxLabelMagnitude || value > kMaxLabelMagnitude)
      throw Error(fmt::format("{}: label '{}' is not an integer within +-{}", where, t[0],
                              kMaxLabelMagnitude));
    int64_t c[4];
    for (int k = 0; k < 4; ++k)
      if (!parse_int(t[2 + k], c[k]) || c[k] < 0 || c[k] > 255)
        throw Error(
            fmt::format("{}: {} '{}' is not an integer in 0-255", where, "RGBA"[k], t[2 + k]));
    LabelEntry e;
    e.value = static_cast<int32_t>(value);
    e.name = std::string(t[1]);
    e.color = display_to_linear(glm::vec3(c[0], c[1], c[2]) / 255.0f);  // as FreeSurfer shows it
    e.opacity = 1.0f - static_cast<float>(c[3]) / 255.0f;  // A is transparency: 0 is opaque
    e.visible = value != 0;                                // label 0 is background
    entries.push_back(std::move(e));
  }
  return entries;
}

}  // namespace imx::labels_detail
