// BrainNet Viewer's connectomes: a .node text file, one node a line ("x y z colour size name",
// MNI RAS mm; a name of "-" is no name; '#' starts a comment), and an optional .edge text file,
// the n x n matrix of weights, one row a line, numbers separated by blanks or commas ('#' and
// MATLAB's '%' start comments).
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "intermix/streamlines.hpp"

namespace imx::detail {

// The nodes (x and y negated: world LPS) and, from `edge` (or, without one, the .edge file of
// the same stem beside `node` when there is one, with a note), the edges: every nonzero entry
// above the diagonal. The matrix must be symmetric, or triangular (one triangle zero: the
// other is used, with a note). Throws imx::Error naming the file, line and field: a line
// without six columns, a value that is not a finite number, no nodes, a matrix that is not
// n x n for the n nodes, an asymmetric matrix (naming the first pair that differs).
Connectome read_brainnet(const std::filesystem::path& node,
                         const std::optional<std::filesystem::path>& edge,
                         std::vector<std::string>& notes);

}  // namespace imx::detail
