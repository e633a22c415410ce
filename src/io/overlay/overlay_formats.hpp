// The surface-overlay formats' table of the format registry: per-vertex values that colour the
// surface given before them. read_vertex_overlay and is_overlay_file choose here.
#pragma once
#include <filesystem>
#include <span>

#include "io/overlay/vertex_overlay.hpp"
#include "io/registry/format_registry.hpp"

namespace imx::detail {

struct OverlayFormat {
  FormatInfo info;
  // `array` picks one of several arrays or maps (GIfTI data arrays), -1 the first.
  VertexOverlay (*read)(const std::filesystem::path&, int array);
};

std::span<const OverlayFormat> overlay_formats_table();

const OverlayFormat* find_overlay_format(const FileProbe& probe);

}  // namespace imx::detail
