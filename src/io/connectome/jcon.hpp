// NiiVue's connectome JSON (.jcon, or .json), in either of the layouts NiiVue's loader takes:
// the dense one, {"nodes": {"names", "X", "Y", "Z", "Color", "Size"}, "edges": [n * n numbers,
// row by row]}, and the sparse one, {"nodes": [{"name", "x", "y", "z", "colorValue",
// "sizeValue"}], "edges": [{"first", "second", "colorValue"}]}; both with optional display
// fields (nodeColormap, edgeMin, ...). Coordinates are MNI RAS mm. NiiVue's loader also takes
// FreeSurfer's point set ({"data_type": "fs_pointset", "points": [{"coordinates": {x, y, z},
// "comments": [{"text"}]}], "vox2ras"}) as nodes without edges.
#pragma once
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "intermix/streamlines.hpp"

namespace imx::detail {

// The nodes (x and y negated: world LPS), the edges and the display fields. Of a dense matrix,
// NiiVue draws the upper triangle only (row < column): so do we, with a note where the lower
// triangle says otherwise; the diagonal is not drawn. Sparse edges given as (second, first) are
// turned round; self-connections and repeated pairs are dropped with a note. Throws imx::Error
// naming the file and the field: not JSON, neither layout, a count that disagrees with the
// number of nodes (names, X, Color, an n x n matrix), an edge naming a node that does not
// exist, a value that is not a finite number, a point set in tkreg space (its volume unknown).
Connectome read_jcon(const std::filesystem::path& file, std::vector<std::string>& notes);

// Whether `head`, the first bytes of a .json file (any length; the whole file is surest), is a
// connectome NiiVue would read: a top-level object with "nodes" and "edges" (or, where the head
// ends before "edges" could be seen, "nodes" holding connectome node fields, or NiiVue's
// display fields), or a FreeSurfer point set (top-level "data_type": "fs_pointset").
bool looks_like_connectome_json(std::string_view head);

}  // namespace imx::detail
