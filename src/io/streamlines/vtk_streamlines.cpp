// VTK polylines as streamlines: the polydata parsers keep the LINES cells on request; here each
// cell's points (and point and cell data) are gathered in its order.
#include "io/streamlines/vtk_streamlines.hpp"

#include <cerrno>
#include <cmath>
#include <fstream>
#include <string_view>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/mesh/polydata.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"

namespace imx::detail {
namespace {

// Legacy (true) or XML (false), by the file's first bytes.
bool is_legacy(const std::filesystem::path& file, const std::string& what) {
  require_regular_file(file);
  std::ifstream in = open_input_stream(file, what);
  std::string head(256, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  if (head.starts_with("\x1f\x8b"))
    throw Error(fmt::format("{}: gzip data: inflate it before reading it as VTK polydata", what));
  if (head.starts_with("# vtk DataFile")) return true;
  std::string_view rest = head;
  if (rest.starts_with("\xef\xbb\xbf")) rest.remove_prefix(3);  // a UTF-8 byte order mark
  if (trim(rest).starts_with("<")) return false;
  throw Error(
      fmt::format("{}: neither legacy VTK ('# vtk DataFile Version') nor VTK XML polydata", what));
}

}  // namespace

Streamlines read_vtk_streamlines(const std::filesystem::path& file,
                                 std::vector<std::string>& notes) {
  const std::string what = file.string();
  const PolyDataFile poly =
      is_legacy(file, what) ? read_vtk_legacy(file, true) : read_vtp(file, true);
  const std::vector<glm::vec3>& positions = poly.mesh.positions;
  const PolyLines& lines = poly.lines;
  const size_t count = lines.offsets.size() - 1;
  for (size_t c = 0; c < count; ++c)
    for (uint64_t k = lines.offsets[c]; k < lines.offsets[c + 1]; ++k)
      if (lines.indices[k] < 0 || static_cast<uint64_t>(lines.indices[k]) >= positions.size())
        throw Error(fmt::format("{}: line cell {} uses point {}, but the file has {} points", what,
                                c, lines.indices[k], positions.size()));
  if (lines.indices.size() > UINT32_MAX)
    throw Error(fmt::format("{}: the lines run through {} points, more than intermix reads ({})",
                            what, lines.indices.size(), UINT32_MAX));

  std::vector<const MeshPointData*> point_arrays, line_arrays;
  std::vector<std::string> unread;
  for (const MeshPointData& d : poly.point_data)
    (d.components == 1 ? point_arrays.push_back(&d) : unread.push_back(d.name));
  for (const MeshPointData& d : poly.line_data)
    (d.components == 1 ? line_arrays.push_back(&d) : unread.push_back(d.name));
  for (const std::string& name : unread)
    notes.push_back(fmt::format("array '{}' left unread: it has more than one component", name));
  check_memory(lines.indices.size() * (sizeof(glm::vec3) + 4 * point_arrays.size()) +
                   count * 4 * (1 + line_arrays.size()),
               fmt::format("{} (streamlines)", what));

  Streamlines out;
  out.points.reserve(lines.indices.size());
  out.offsets.reserve(count + 1);
  for (const MeshPointData* d : point_arrays) {
    out.point_values.push_back({d->name, {}});
    out.point_values.back().values.reserve(lines.indices.size());
  }
  for (const MeshPointData* d : line_arrays) out.streamline_values.push_back({d->name, {}});
  // Without a SPACE tag, RAS: what tractography tools write (MRtrix's tckconvert, DSI Studio,
  // TractSeg) and how NiiVue reads them; a mesh without one stays LPS (mesh_space.hpp).
  const bool ras = poly.space != MeshSpace::lps;
  uint64_t too_short = 0, not_finite = 0;
  for (size_t c = 0; c < count; ++c) {
    const uint64_t first = lines.offsets[c], end = lines.offsets[c + 1];
    if (end - first < 2) {
      ++too_short;
      continue;
    }
    bool finite = true;
    for (uint64_t k = first; k < end; ++k) {
      const glm::vec3& p = positions[static_cast<size_t>(lines.indices[k])];
      finite = finite && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    }
    if (!finite) {
      ++not_finite;
      continue;
    }
    for (uint64_t k = first; k < end; ++k) {
      const auto i = static_cast<size_t>(lines.indices[k]);
      const glm::vec3& p = positions[i];
      out.points.push_back(ras ? glm::vec3(-p.x, -p.y, p.z) : p);
      for (size_t a = 0; a < point_arrays.size(); ++a)
        out.point_values[a].values.push_back(static_cast<float>(point_arrays[a]->values[i]));
    }
    out.offsets.push_back(static_cast<uint32_t>(out.points.size()));
    for (size_t a = 0; a < line_arrays.size(); ++a)
      out.streamline_values[a].values.push_back(static_cast<float>(line_arrays[a]->values[c]));
  }
  notes.push_back(poly.space ? fmt::format("SPACE={} in the file{}", ras ? "RAS" : "LPS",
                                           ras ? ": x and y negated to LPS" : "")
                             : "no SPACE tag: coordinates taken as RAS (as tractography tools "
                               "write them), x and y negated to LPS");
  if (too_short > 0)
    notes.push_back(fmt::format("{} line cells of fewer than 2 points left out", too_short));
  if (not_finite > 0)
    notes.push_back(
        fmt::format("{} line cells left out: their points are not all finite", not_finite));
  if (count == 0) notes.push_back("the file holds no line cells");
  return out;
}

}  // namespace imx::detail
