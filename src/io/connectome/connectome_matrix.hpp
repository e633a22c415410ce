// The edges of a square n x n weight matrix (row by row): how NiiVue's dense JSON and BrainNet's
// .edge file become Connectome::edges, and where the matrix is not symmetric.
#pragma once
#include <cstddef>
#include <optional>
#include <vector>

#include "intermix/streamlines.hpp"

namespace imx::detail {

struct MatrixEntry {
  size_t row = 0, column = 0;
};

// The first entry below the diagonal (row > column, row by row) that differs from its mirror.
std::optional<MatrixEntry> first_asymmetry(const std::vector<float>& matrix, size_t n);

// Whether every entry strictly above (upper) or strictly below the diagonal is zero.
bool triangle_is_zero(const std::vector<float>& matrix, size_t n, bool upper);

// One edge (a < b) per nonzero entry of the upper triangle, or of the lower one (its (b, a)).
std::vector<ConnectomeEdge> triangle_edges(const std::vector<float>& matrix, size_t n, bool upper);

}  // namespace imx::detail
