// The label-table formats' table of the format registry: read_label_table chooses its reader
// here.
#pragma once
#include <filesystem>
#include <span>
#include <vector>

#include "intermix/labels.hpp"
#include "io/registry/format_registry.hpp"

namespace imx::labels_detail {

struct LabelTableFormat {
  detail::FormatInfo info;
  std::vector<LabelEntry> (*read)(const std::filesystem::path&, int layer);
};

std::span<const LabelTableFormat> label_table_formats_table();

// The readers behind the rows (label_table.cpp): a 3D Slicer segmentation's segments of one
// layer, and a text table (FreeSurfer LUT or ITK-SNAP, told apart by the first row's quotes).
std::vector<LabelEntry> read_slicer_segments(const std::filesystem::path& file, int layer);
std::vector<LabelEntry> read_text_table(const std::filesystem::path& file, int layer);

}  // namespace imx::labels_detail
