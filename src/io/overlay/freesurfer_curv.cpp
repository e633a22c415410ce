// FreeSurfer's new curvature format (curv, thickness, sulc, area, volume, ...).
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/overlay/vertex_overlay.hpp"
#include "io/streams/byte_cursor.hpp"

namespace imx::detail {

bool is_freesurfer_curv(const std::string& bytes) {
  return bytes.size() >= 3 && static_cast<uint8_t>(bytes[0]) == 0xFF &&
         static_cast<uint8_t>(bytes[1]) == 0xFF && static_cast<uint8_t>(bytes[2]) == 0xFF;
}

VertexOverlay read_freesurfer_curv(const std::string& bytes, const std::string& what) {
  if (!is_freesurfer_curv(bytes))
    throw Error(
        fmt::format("{}: not a FreeSurfer curvature file in the new format (magic "
                    "0xFFFFFF); the old 3-byte format is not read",
                    what));
  ByteCursor in(bytes, what, true);
  in.take(3, "the magic number");
  const int32_t vnum = in.read<int32_t>("the vertex count");
  const int32_t fnum = in.read<int32_t>("the face count");
  const int32_t per_vertex = in.read<int32_t>("the values per vertex");
  if (vnum <= 0 || fnum < 0)
    throw Error(fmt::format("{}: {} vertices and {} faces is not a surface's", what, vnum, fnum));
  if (per_vertex != 1)
    throw Error(fmt::format("{}: {} values per vertex; intermix reads curvature files of one", what,
                            per_vertex));
  in.need(uint64_t{4} * static_cast<uint64_t>(vnum), fmt::format("{} float32 values", vnum));
  check_memory(uint64_t{8} * static_cast<uint64_t>(vnum), what);
  VertexOverlay out;
  out.claimed_vertices = static_cast<uint64_t>(vnum);
  out.values.resize(static_cast<size_t>(vnum));
  for (double& v : out.values) v = in.read<float>("a value");
  return out;
}

}  // namespace imx::detail
