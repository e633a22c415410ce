#include "io/overlay/vertex_overlay.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include <fmt/format.h>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "io/mesh/gifti_check.hpp"
#include "io/overlay/overlay_formats.hpp"
#include "io/streams/byte_cursor.hpp"
#include "io/streams/header_text.hpp"

namespace imx::detail {

VertexOverlay read_gifti_vertex_overlay(const std::filesystem::path& file, int array) {
  GiftiOverlay g = read_gifti_overlay(file, array);
  const GiftiArray& a = g.values;
  VertexOverlay out;
  out.claimed_vertices = a.rows;
  out.values.resize(static_cast<size_t>(a.rows));
  visit_gifti_type(a.type, [&]<class T>(T) {
    for (size_t i = 0; i < out.values.size(); ++i) {
      uint8_t b[sizeof(T)];
      std::memcpy(b, a.bytes.data() + i * sizeof(T), sizeof(T));
      if (a.swapped) std::reverse(b, b + sizeof(T));
      T v;
      std::memcpy(&v, b, sizeof(T));
      out.values[i] = static_cast<double>(v);
    }
  });
  out.labels = g.intent == "NIFTI_INTENT_LABEL";
  if (out.labels) {
    if (g.labels.empty())
      throw Error(
          fmt::format("{}: data array {} is NIFTI_INTENT_LABEL, but the file has no "
                      "LabelTable",
                      file.string(), g.index));
    for (const GiftiLabel& l : g.labels)
      out.table.push_back({l.key, std::string(trim(l.name)),
                           glm::vec4(l.rgba[0], l.rgba[1], l.rgba[2], l.rgba[3])});
  }
  return out;
}

bool is_overlay_file(const std::filesystem::path& file) {
  return find_overlay_format(probe_file(file)) != nullptr;
}

VertexOverlay read_vertex_overlay(const std::filesystem::path& file, int array) {
  if (const OverlayFormat* format = find_overlay_format(probe_file(file)))
    return format->read(file, array);
  std::vector<const FormatInfo*> rows;
  for (const OverlayFormat& row : overlay_formats_table()) rows.push_back(&row.info);
  throw Error(fmt::format("{}: '{}' is not a surface overlay format intermix reads (overlays: {})",
                          file.string(), compound_suffix(file), list_formats(rows)));
}

std::vector<double> overlay_values(const VertexOverlay& overlay, size_t vertex_count,
                                   const std::string& what) {
  if (!overlay.members.empty() || (overlay.values.empty() && overlay.labels)) {
    std::vector<double> out(vertex_count, std::numeric_limits<double>::quiet_NaN());
    for (uint32_t v : overlay.members) {
      if (v >= vertex_count)
        throw Error(fmt::format("{}: the label names vertex {}, but the mesh has {} vertices", what,
                                v, vertex_count));
      out[v] = 1.0;
    }
    return out;
  }
  if (overlay.values.size() != vertex_count)
    throw Error(fmt::format("{}: the overlay has {} values, the mesh {} vertices", what,
                            overlay.values.size(), vertex_count));
  return overlay.values;
}

}  // namespace imx::detail
