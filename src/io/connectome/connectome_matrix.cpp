#include "io/connectome/connectome_matrix.hpp"

#include <cstdint>

namespace imx::detail {

std::optional<MatrixEntry> first_asymmetry(const std::vector<float>& matrix, size_t n) {
  for (size_t row = 1; row < n; ++row)
    for (size_t column = 0; column < row; ++column)
      if (matrix[row * n + column] != matrix[column * n + row]) return MatrixEntry{row, column};
  return std::nullopt;
}

bool triangle_is_zero(const std::vector<float>& matrix, size_t n, bool upper) {
  for (size_t row = 0; row < n; ++row)
    for (size_t column = upper ? row + 1 : 0; column < (upper ? n : row); ++column)
      if (matrix[row * n + column] != 0.0f) return false;
  return true;
}

std::vector<ConnectomeEdge> triangle_edges(const std::vector<float>& matrix, size_t n, bool upper) {
  const auto weight = [&](size_t a, size_t b) {
    return upper ? matrix[a * n + b] : matrix[b * n + a];
  };
  size_t count = 0;  // counted first so that the edges take no more memory than they need
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n; ++b) count += weight(a, b) != 0.0f;
  std::vector<ConnectomeEdge> edges;
  edges.reserve(count);
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n; ++b)
      if (const float w = weight(a, b); w != 0.0f)
        edges.push_back({static_cast<uint32_t>(a), static_cast<uint32_t>(b), w});
  return edges;
}

}  // namespace imx::detail
