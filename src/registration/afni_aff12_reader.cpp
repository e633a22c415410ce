// AFNI's affine matrix files (.aff12.1D, from -1Dmatrix_save of 3dAllineate, 3dvolreg and
// 3dWarpDrive): the base-to-source map, x_source = U x_base + v, in AFNI's DICOM order (x to
// the left, y to the back, z up: LPS), row by row: u11 u12 u13 v1 u21 ... v3.
#include <fmt/format.h>

#include "intermix/error.hpp"
#include "registration/transform_readers.hpp"

namespace imx::detail {

glm::dmat4 read_afni_aff12(std::string_view text, const std::string& what) {
  std::vector<std::vector<double>> rows;
  const std::vector<std::string_view> lines = text_lines(text, what);
  for (size_t i = 0; i < lines.size(); ++i) {
    std::string_view line = lines[i].substr(0, lines[i].find('#'));
    std::vector<std::string_view> w = words(line);
    if (w.empty()) continue;
    if (rows.size() >= 3)
      throw Error(
          fmt::format("{}: line {}: more rows than one matrix (a file of one row per "
                      "sub-brick holds several; give one)",
                      what, i + 1));
    std::vector<double> row;
    for (std::string_view s : w)
      row.push_back(parse_number(s, what, fmt::format("line {}", i + 1)));
    rows.push_back(std::move(row));
  }
  std::vector<double> values;
  if (rows.size() == 1 && rows[0].size() == 12) {
    values = rows[0];
  } else if (rows.size() == 3 && rows[0].size() == 4 && rows[1].size() == 4 &&
             rows[2].size() == 4) {
    for (const auto& r : rows) values.insert(values.end(), r.begin(), r.end());
  } else if (rows.size() > 1 && rows[0].size() == 12) {
    throw Error(
        fmt::format("{}: {} rows of 12 numbers (one per sub-brick); give a file of one "
                    "matrix",
                    what, rows.size()));
  } else {
    size_t n = 0;
    for (const auto& r : rows) n += r.size();
    throw Error(
        fmt::format("{}: {} numbers in {} rows; an AFNI matrix is one row of 12 or three "
                    "rows of 4 (truncated?)",
                    what, n, rows.size()));
  }
  double m[3][4];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m[r][c] = values[static_cast<size_t>(4 * r + c)];
  return affine_from_rows(m);
}

}  // namespace imx::detail
