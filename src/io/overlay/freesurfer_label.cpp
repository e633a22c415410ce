// FreeSurfer ASCII labels (.label): the vertices of one region.
#include <cmath>
#include <cstdint>
#include <optional>
#include <string_view>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/overlay/vertex_overlay.hpp"
#include "io/streams/header_text.hpp"

namespace imx::detail {

VertexOverlay read_freesurfer_label(const std::string& bytes, const std::string& what,
                                    const std::string& name) {
  std::string_view text = bytes;
  size_t line_number = 0;
  auto next_line = [&]() -> std::optional<std::string_view> {
    if (text.empty()) return std::nullopt;
    const size_t eol = std::min(text.find('\n'), text.size());
    std::string_view line = trim(text.substr(0, eol));
    text.remove_prefix(std::min(eol + 1, text.size()));
    ++line_number;
    return line;
  };
  // Line 1 is a comment ("#!ascii label ..."), line 2 the count (nibabel skips both).
  if (!next_line()) throw Error(fmt::format("{}: the file is empty, not a FreeSurfer label", what));
  const std::optional<std::string_view> count_line = next_line();
  const std::optional<int64_t> count =
      count_line ? parse_header_number<int64_t>(*count_line) : std::nullopt;
  if (!count || *count < 0)
    throw Error(fmt::format("{}: line 2 '{}' is not the label's vertex count", what,
                            shown(count_line.value_or(""))));
  VertexOverlay out;
  out.labels = true;
  out.table.push_back({1, name, glm::vec4(1.0f, 0.85f, 0.0f, 1.0f)});
  int64_t rows = 0;
  while (std::optional<std::string_view> line = next_line()) {
    if (line->empty()) continue;
    const auto words = split_words(*line);
    std::optional<int64_t> vertex = parse_header_number<int64_t>(words.front());
    if (words.size() != 5 || !vertex || *vertex < 0 || *vertex >= (int64_t{1} << 31))
      throw Error(fmt::format("{}: line {} '{}' is not 'vertex x y z value'", what, line_number,
                              shown(*line)));
    for (size_t w = 1; w < 5; ++w)
      if (!parse_header_number<double>(words[w]))
        throw Error(fmt::format("{}: line {} '{}' is not 'vertex x y z value'", what, line_number,
                                shown(*line)));
    ++rows;
    check_memory(uint64_t{4} * (out.members.size() + 1), what);
    out.members.push_back(static_cast<uint32_t>(*vertex));
  }
  if (rows != *count)
    throw Error(
        fmt::format("{}: line 2 says {} vertices, but the file lists {}", what, *count, rows));
  return out;
}

}  // namespace imx::detail
