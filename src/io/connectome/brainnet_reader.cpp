#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/connectome/brainnet.hpp"
#include "io/connectome/connectome_matrix.hpp"
#include "io/streams/byte_cursor.hpp"
#include "io/streams/regular_file.hpp"

namespace imx::detail {
namespace {

constexpr size_t kNodeColumns = 6;  // x y z colour size name

bool is_separator(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == ',' || c == '\v';
}

// Calls take(line_number, text) for each line of `bytes`, its comment (from any of
// `comment_starts`) cut off.
template <class Take>
void for_each_line(std::string_view bytes, std::string_view comment_starts, Take take) {
  size_t line = 0;
  while (!bytes.empty()) {
    const size_t eol = bytes.find('\n');
    std::string_view text = bytes.substr(0, eol);
    bytes.remove_prefix(eol == std::string_view::npos ? bytes.size() : eol + 1);
    ++line;
    if (const size_t hash = text.find_first_of(comment_starts); hash != std::string_view::npos)
      text = text.substr(0, hash);
    take(line, text);
  }
}

// The next word of `text` from `at` (separators skipped), advancing `at`; empty at the end.
std::string_view next_word(std::string_view text, size_t& at) {
  while (at < text.size() && is_separator(text[at])) ++at;
  const size_t start = at;
  while (at < text.size() && !is_separator(text[at])) ++at;
  return text.substr(start, at - start);
}

// A finite number as float; false for anything else (text, "NaN", "Inf", out of float range).
bool parse_number(std::string_view word, float& out) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);  // from_chars takes no '+'
  double d = 0.0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), d);
  if (ec != std::errc() || end != word.data() + word.size() || word.empty()) return false;
  out = static_cast<float>(d);
  return std::isfinite(out);
}

// A word as a message shows it: cut short, bytes outside printable ASCII as '?'.
std::string shown(std::string_view word) {
  std::string s(word.substr(0, 40));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) c = '?';
  return s;
}

std::vector<ConnectomeNode> read_nodes(const std::filesystem::path& file) {
  const std::string what = file.string();
  const std::string bytes = read_file_bytes(file);
  std::vector<ConnectomeNode> nodes;
  for_each_line(bytes, "#", [&](size_t line, std::string_view text) {
    std::string_view words[kNodeColumns];
    size_t count = 0, at = 0;
    for (std::string_view w = next_word(text, at); !w.empty(); w = next_word(text, at)) {
      if (count == kNodeColumns)
        throw Error(
            fmt::format("{}: line {}: more than 6 columns (x y z colour size name; a "
                        "name may not hold blanks)",
                        what, line));
      words[count++] = w;
    }
    if (count == 0) return;
    if (count != kNodeColumns)
      throw Error(
          fmt::format("{}: line {}: {} columns, but a node line has 6 (x y z colour "
                      "size name)",
                      what, line, count));
    static constexpr const char* kFields[] = {"x", "y", "z", "colour", "size"};
    float v[5];
    for (size_t i = 0; i < 5; ++i)
      if (!parse_number(words[i], v[i]))
        throw Error(fmt::format("{}: line {}: {} is '{}', not a finite number", what, line,
                                kFields[i], shown(words[i])));
    ConnectomeNode& node = nodes.emplace_back();
    node.position = {-v[0], -v[1], v[2]};  // MNI RAS mm to world LPS
    node.value = v[3];
    node.size = v[4];
    if (words[5] != "-") node.name = std::string(words[5]);  // "-": BrainNet's "no name"
  });
  if (nodes.empty())
    throw Error(fmt::format("{}: no nodes (no line of x y z colour size name)", what));
  if (nodes.size() > UINT32_MAX)
    throw Error(fmt::format("{}: {} nodes, too many", what, nodes.size()));
  return nodes;
}

// The n x n matrix of `file`, one row a line, after checking that its size can hold one.
std::vector<float> read_matrix(const std::filesystem::path& file, size_t n) {
  const std::string what = file.string();
  require_regular_file(file);
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) throw FileError(fmt::format("{}: cannot read the file size", what), ec.value());
  // Each value takes at least one character and a separator: n^2 values, 2 n^2 - 1 bytes.
  const uint64_t values = uint64_t{n} * n;
  if (n >= (uint64_t{1} << 31) || 2 * values - 1 > size)
    throw Error(
        fmt::format("{}: {} nodes need a {} x {} matrix ({} values), more than the "
                    "file's {} bytes can hold",
                    what, n, n, n, values, size));
  check_memory(size + sizeof(float) * values, what + " (its edge matrix)");
  const std::string bytes = read_file_bytes(file);
  std::vector<float> matrix(static_cast<size_t>(values));
  size_t row = 0;
  for_each_line(bytes, "#%", [&](size_t line, std::string_view text) {
    size_t column = 0, at = 0;
    for (std::string_view w = next_word(text, at); !w.empty(); w = next_word(text, at)) {
      if (row == n)
        throw Error(fmt::format("{}: line {}: more than {} rows, but there are {} nodes", what,
                                line, n, n));
      if (column == n)
        throw Error(
            fmt::format("{}: line {}: row {} has more than {} values, but there are {} "
                        "nodes",
                        what, line, row + 1, n, n));
      if (!parse_number(w, matrix[row * n + column]))
        throw Error(fmt::format("{}: line {}: row {}, column {} is '{}', not a finite number", what,
                                line, row + 1, column + 1, shown(w)));
      ++column;
    }
    if (column == 0) return;  // a blank or comment line
    if (column != n)
      throw Error(fmt::format("{}: line {}: row {} has {} values, but there are {} nodes", what,
                              line, row + 1, column, n));
    ++row;
  });
  if (row != n)
    throw Error(fmt::format("{}: {} rows, but there are {} nodes (an n x n matrix is needed)", what,
                            row, n));
  return matrix;
}

// The edges of a symmetric matrix, or of a triangular one's nonzero triangle.
std::vector<ConnectomeEdge> matrix_edges(const std::vector<float>& matrix, size_t n,
                                         const std::string& what, std::vector<std::string>& notes) {
  const std::optional<MatrixEntry> e = first_asymmetry(matrix, n);
  if (!e) return triangle_edges(matrix, n, true);
  if (triangle_is_zero(matrix, n, false)) {
    notes.push_back(
        fmt::format("{}: the lower triangle is zero: the upper one gives the edges", what));
    return triangle_edges(matrix, n, true);
  }
  if (triangle_is_zero(matrix, n, true)) {
    notes.push_back(
        fmt::format("{}: the upper triangle is zero: the lower one gives the edges", what));
    return triangle_edges(matrix, n, false);
  }
  throw Error(
      fmt::format("{}: the matrix is not symmetric: row {}, column {} is {}, but row {}, "
                  "column {} is {} (counting from 1)",
                  what, e->row + 1, e->column + 1, matrix[e->row * n + e->column], e->column + 1,
                  e->row + 1, matrix[e->column * n + e->row]));
}

}  // namespace

Connectome read_brainnet(const std::filesystem::path& node,
                         const std::optional<std::filesystem::path>& edge,
                         std::vector<std::string>& notes) {
  Connectome out;
  out.nodes = read_nodes(node);
  std::optional<std::filesystem::path> edge_file = edge;
  if (!edge_file) {
    std::filesystem::path beside = node;
    beside.replace_extension(".edge");
    std::error_code ec;
    if (std::filesystem::is_regular_file(beside, ec)) {
      notes.push_back(
          fmt::format("{}: its edges are read from {}, beside it", node.string(), beside.string()));
      edge_file = beside;
    } else {
      notes.push_back(
          fmt::format("{}: no edges (no {} beside it)", node.string(), beside.filename().string()));
    }
  }
  if (edge_file) {
    const size_t n = out.nodes.size();
    out.edges = matrix_edges(read_matrix(*edge_file, n), n, edge_file->string(), notes);
  }
  return out;
}

}  // namespace imx::detail
