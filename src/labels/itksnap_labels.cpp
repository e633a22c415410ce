// ITK-SNAP's label description file: `IDX R G B A VIS MSH "name"` per row.
#include <fmt/format.h>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "labels/colour_table_readers.hpp"
#include "labels/label_text.hpp"

namespace imx::labels_detail {

std::vector<LabelEntry> parse_itksnap_labels(std::string_view text, const std::string& what) {
  std::vector<LabelEntry> entries;
  const std::vector<std::string_view> rows = lines(text);
  for (size_t n = 0; n < rows.size(); ++n) {
    if (skippable(rows[n])) continue;
    const std::string where = fmt::format("{}: line {}", what, n + 1);
    const std::string_view row = rows[n];
    const size_t open = row.find('"'), close = row.rfind('"');
    if (open == std::string_view::npos || close == open)
      throw Error(where +
                  ": no quoted label name; an ITK-SNAP row is 'IDX R G B A VIS MSH \"name\"'");
    for (char ch : row.substr(close + 1))
      if (ch != ' ' && ch != '\t') throw Error(where + ": text after the quoted label name");
    const auto t = tokens(row.substr(0, open));
    if (t.size() != 7)
      throw Error(
          fmt::format("{}: {} numbers before the name; an ITK-SNAP row has 7 (IDX R G B A "
                      "VIS MSH)",
                      where, t.size()));
    int64_t value = 0;
    if (!parse_int(t[0], value) || value < -kMaxLabelMagnitude || value > kMaxLabelMagnitude)
      throw Error(fmt::format("{}: label '{}' is not an integer within +-{}", where, t[0],
                              kMaxLabelMagnitude));
    int64_t c[3];
    for (int k = 0; k < 3; ++k)
      if (!parse_int(t[1 + k], c[k]) || c[k] < 0 || c[k] > 255)
        throw Error(
            fmt::format("{}: {} '{}' is not an integer in 0-255", where, "RGB"[k], t[1 + k]));
    double alpha = 0.0;
    if (!parse_double(t[4], alpha) || alpha < 0.0 || alpha > 1.0)
      throw Error(fmt::format("{}: A '{}' is not a number in [0, 1]", where, t[4]));
    int64_t vis = 0, mesh = 0;
    if (!parse_int(t[5], vis) || (vis != 0 && vis != 1))
      throw Error(fmt::format("{}: VIS '{}' is not 0 or 1", where, t[5]));
    if (!parse_int(t[6], mesh) || (mesh != 0 && mesh != 1))
      throw Error(fmt::format("{}: MSH '{}' is not 0 or 1", where, t[6]));
    LabelEntry e;
    e.value = static_cast<int32_t>(value);
    e.name = std::string(row.substr(open + 1, close - open - 1));
    e.color = display_to_linear(glm::vec3(c[0], c[1], c[2]) / 255.0f);  // as ITK-SNAP shows it
    e.opacity = static_cast<float>(alpha);
    e.visible = vis == 1 && value != 0;  // label 0 ("Clear Label") is background
    entries.push_back(std::move(e));
  }
  return entries;
}

}  // namespace imx::labels_detail
