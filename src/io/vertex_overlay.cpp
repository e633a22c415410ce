#include "io/vertex_overlay.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include <fmt/format.h>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "io/byte_cursor.hpp"
#include "io/gifti_check.hpp"
#include "io/header_text.hpp"

namespace imx::detail {
namespace {

VertexOverlay gifti_overlay(const std::filesystem::path& file, int array) {
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

}  // namespace

bool is_overlay_file(const std::filesystem::path& file) {
  const std::string ext = lower(file.extension().string());
  if (ext == ".annot" || ext == ".label") return true;
  std::ifstream in(file, std::ios::binary);
  if (!in) return false;
  if (ext == ".gii") {
    // GIfTI is XML: a surface names NIFTI_INTENT_POINTSET; func, shape and label files do not.
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    return text.find("NIFTI_INTENT_POINTSET") == std::string::npos;
  }
  std::string head(3, '\0');
  in.read(head.data(), 3);
  return in.gcount() == 3 && is_freesurfer_curv(head);
}

VertexOverlay read_vertex_overlay(const std::filesystem::path& file, int array) {
  const std::string ext = lower(file.extension().string());
  if (ext == ".gii") return gifti_overlay(file, array);
  if (array >= 0)
    throw Error(fmt::format("{}: \"array\" picks a data array of a GIfTI file; this is not one",
                            file.string()));
  const std::string bytes = read_file_bytes(file);
  if (ext == ".annot") return read_freesurfer_annot(bytes, file.string());
  if (ext == ".label") return read_freesurfer_label(bytes, file.string(), file.stem().string());
  if (is_freesurfer_curv(bytes)) return read_freesurfer_curv(bytes, file.string());
  throw Error(
      fmt::format("{}: not an overlay intermix reads (GIfTI .gii, FreeSurfer curvature "
                  "such as lh.thickness, .annot or .label)",
                  file.string()));
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
