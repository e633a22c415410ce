// FreeSurfer's linear transform arrays (.lta: mri_robust_register, bbregister, lta_convert).
// The matrix maps the source ("src", the moving volume) to the destination ("dst"): RAS points
// to RAS points (type 1, LINEAR_RAS_TO_RAS) or voxel indices to voxel indices (type 0,
// LINEAR_VOX_TO_VOX, through the geometry the file records for both volumes).
#include <cmath>
#include <map>
#include <optional>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "intermix/error.hpp"
#include "registration/transform_readers.hpp"

namespace imx::detail {
namespace {

// A volume info block: dims, voxel sizes, the directions of the voxel axes in RAS, and the RAS
// point at voxel dims / 2.
struct VolumeGeometry {
  bool valid = false;
  std::map<std::string, std::vector<double>> fields;
};

std::string_view strip_comment(std::string_view line) {
  return line.substr(0, line.find('#'));
}

std::string trimmed(std::string_view s) {
  std::vector<std::string_view> w = words(s);
  std::string out;
  for (size_t i = 0; i < w.size(); ++i) {
    if (i > 0) out += ' ';
    out += w[i];
  }
  return out;
}

glm::dmat4 vox2ras(const VolumeGeometry& g, const std::string& block, const std::string& what) {
  if (!g.valid)
    throw Error(
        fmt::format("{}: a LINEAR_VOX_TO_VOX transform needs the {} volume info, which "
                    "is missing or not valid",
                    what, block));
  auto field = [&](const char* name) {
    auto it = g.fields.find(name);
    if (it == g.fields.end() || it->second.size() != 3)
      throw Error(fmt::format("{}: {} volume info: '{}' needs 3 numbers", what, block, name));
    return glm::dvec3(it->second[0], it->second[1], it->second[2]);
  };
  const glm::dvec3 dims = field("volume"), size = field("voxelsize");
  // Checked here, so that a degenerate grid is named rather than found as a singular matrix.
  if (!(size.x > 0.0 && size.y > 0.0 && size.z > 0.0))
    throw Error(
        fmt::format("{}: {} volume info: voxelsize {:g} {:g} {:g}: each size must be a "
                    "positive number of mm",
                    what, block, size.x, size.y, size.z));
  for (const char* axis : {"xras", "yras", "zras"}) {
    const glm::dvec3 d = field(axis);
    if (!(glm::length(d) > 1e-6))
      throw Error(fmt::format("{}: {} volume info: {} {:g} {:g} {:g} is not a direction", what,
                              block, axis, d.x, d.y, d.z));
  }
  const glm::dmat3 directions(field("xras"), field("yras"), field("zras"));
  glm::dmat3 axes = directions;
  for (int a = 0; a < 3; ++a) axes[a] *= size[a];
  glm::dmat4 m(axes);
  m[3] = glm::dvec4(field("cras") - axes * (dims / 2.0), 1.0);
  return m;
}

}  // namespace

glm::dmat4 read_lta(std::string_view text, const std::string& what) {
  std::optional<int> type;
  std::optional<int> nxforms;
  std::vector<double> matrix;
  bool in_matrix = false;
  VolumeGeometry geometry[2];
  int block = -1;  // 0 src, 1 dst
  const std::vector<std::string_view> lines = text_lines(text, what);
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::string line = trimmed(strip_comment(lines[i]));
    if (line.empty()) continue;
    const std::string where = fmt::format("line {}", i + 1);
    if (line == "src volume info" || line == "dst volume info") {
      block = line[0] == 's' ? 0 : 1;
      in_matrix = false;
      continue;
    }
    const size_t eq = line.find('=');
    if (eq == std::string::npos) {
      if (block >= 0) continue;  // "subject NAME", "fscale X" follow the blocks
      std::vector<std::string_view> w = words(line);
      if (!type) throw Error(fmt::format("{}: {}: expected \"type = N\" first", what, where));
      if (!in_matrix) {
        // "1 4 4": transforms, rows, columns
        if (w.size() != 3 || w[0] != "1" || w[1] != "4" || w[2] != "4")
          throw Error(fmt::format("{}: {}: expected the matrix size \"1 4 4\", got '{}'", what,
                                  where, line.substr(0, 40)));
        in_matrix = true;
        continue;
      }
      for (std::string_view v : w) {
        if (matrix.size() == 16)
          throw Error(fmt::format("{}: {}: more than 16 matrix entries", what, where));
        matrix.push_back(parse_number(v, what, fmt::format("{} (matrix)", where)));
      }
      continue;
    }
    const std::string key = trimmed(line.substr(0, eq));
    const std::vector<std::string_view> values = words(std::string_view(line).substr(eq + 1));
    if (block >= 0) {
      if (key == "valid") {
        geometry[block].valid = values.size() == 1 && values[0] == "1";
      } else if (key == "volume" || key == "voxelsize" || key == "xras" || key == "yras" ||
                 key == "zras" || key == "cras") {
        std::vector<double>& v = geometry[block].fields[key];
        v.clear();
        for (std::string_view s : values)
          v.push_back(parse_number(s, what, where + " (" + key + ")"));
      }
      continue;  // filename and others say nothing of the geometry
    }
    if (key == "type" || key == "nxforms") {
      if (values.size() != 1)
        throw Error(fmt::format("{}: {}: '{}' needs one number", what, where, key));
      const double v = parse_number(values[0], what, where + " (" + key + ")");
      if (v != std::floor(v) || std::abs(v) > 1e6)
        throw Error(fmt::format("{}: {}: '{}' must be an integer", what, where, key));
      (key == "type" ? type : nxforms) = static_cast<int>(v);
    }
    // mean and sigma describe how the registration was found, not the matrix.
  }
  if (!type) throw Error(fmt::format("{}: no \"type = N\" line: not an LTA file", what));
  if (*type != 0 && *type != 1)
    throw Error(
        fmt::format("{}: transform type {}; read are 0 (LINEAR_VOX_TO_VOX) and 1 "
                    "(LINEAR_RAS_TO_RAS); convert others with lta_convert",
                    what, *type));
  if (nxforms && *nxforms != 1)
    throw Error(fmt::format("{}: nxforms = {}; one transform is read", what, *nxforms));
  if (matrix.size() != 16)
    throw Error(fmt::format("{}: {} matrix entries; an LTA holds 4 rows of 4 (truncated?)", what,
                            matrix.size()));
  const double last[4] = {0.0, 0.0, 0.0, 1.0};
  for (int c = 0; c < 4; ++c)
    if (std::abs(matrix[static_cast<size_t>(12 + c)] - last[c]) > 1e-6)
      throw Error(
          fmt::format("{}: the matrix's last row must be 0 0 0 1 (an affine matrix)", what));
  double rows[3][4];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) rows[r][c] = matrix[static_cast<size_t>(4 * r + c)];
  glm::dmat4 ras = affine_from_rows(rows);
  if (*type == 0)
    ras = vox2ras(geometry[1], "dst", what) * ras * glm::inverse(vox2ras(geometry[0], "src", what));
  const glm::dmat4 flip(glm::dvec4(-1, 0, 0, 0), glm::dvec4(0, -1, 0, 0), glm::dvec4(0, 0, 1, 0),
                        glm::dvec4(0, 0, 0, 1));
  return flip * ras * flip;  // RAS to LPS on both sides
}

}  // namespace imx::detail
