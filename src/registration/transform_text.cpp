// Text handling shared by the transform readers: lines, words and strict numbers.
#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "registration/transform_readers.hpp"

namespace imx::detail {

std::vector<std::string_view> text_lines(std::string_view text, const std::string& what) {
  if (text.find('\0') != std::string_view::npos)
    throw Error(fmt::format("{}: holds a NUL byte: not a text transform file", what));
  std::vector<std::string_view> lines;
  size_t pos = 0;
  while (pos < text.size()) {
    size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string_view line = text.substr(pos, eol - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    pos = eol + 1;
  }
  return lines;
}

std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  size_t pos = 0;
  auto space = [](char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f' || c == '\r'; };
  while (pos < line.size()) {
    while (pos < line.size() && space(line[pos])) ++pos;
    size_t end = pos;
    while (end < line.size() && !space(line[end])) ++end;
    if (end > pos) out.push_back(line.substr(pos, end - pos));
    pos = end;
  }
  return out;
}

double parse_number(std::string_view token, const std::string& what, std::string_view field) {
  std::string_view digits = token;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);  // from_chars refuses it
  double value = 0.0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  const std::string shown(token.substr(0, 40));
  if (ec == std::errc::result_out_of_range)
    throw Error(fmt::format("{}: {}: {} is out of range", what, field, shown));
  if (ec != std::errc() || end != digits.data() + digits.size())
    throw Error(fmt::format("{}: {}: '{}' is not a number", what, field, shown));
  if (!std::isfinite(value))
    throw Error(
        fmt::format("{}: {}: {} is not a finite number (NaN or infinity)", what, field, shown));
  return value;
}

glm::dmat4 affine_from_rows(const double (&rows)[3][4]) {
  glm::dmat4 m(1.0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = rows[r][c];
  return m;
}

}  // namespace imx::detail
