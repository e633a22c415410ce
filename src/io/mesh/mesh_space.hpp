// The coordinate space of a mesh file: 3D Slicer's SPACE=RAS / SPACE=LPS header comments, and
// the RAS to LPS conversion.
#pragma once
#include <filesystem>
#include <optional>
#include <string_view>

#include "intermix/io.hpp"
#include "intermix/mesh.hpp"

namespace imx::detail {

// The space named in the header comment where 3D Slicer writes one, by format (`ext` lower
// case): the first line of an ASCII STL ("solid 3D Slicer output. SPACE=RAS") or the 80-byte
// header of a binary one, the comment lines that open an OBJ file, the comment lines of a PLY
// header. nullopt when the header names none or the format has no such place.
std::optional<MeshSpace> header_space(const std::filesystem::path& file, std::string_view ext);

// The space that the first "SPACE=RAS" or "SPACE=LPS" in `text` names, if any.
std::optional<MeshSpace> find_space_tag(std::string_view text);

// RAS to LPS (or back): x and y of positions and normals negated. A rotation by 180 degrees
// about z, so the winding and the facing of every triangle stay as they were.
void flip_ras_lps(Mesh& mesh);

}  // namespace imx::detail
