// The volume formats' table of the format registry: read_volume, read_volume_header and
// read_volume_region choose their reader here.
#pragma once
#include <filesystem>
#include <span>

#include "intermix/volume.hpp"
#include "io/registry/format_registry.hpp"

namespace imx::detail {

struct VolumeFormat {
  FormatInfo info;
  VolumeData (*whole)(const std::filesystem::path&, int frame);
  VolumeHeader (*header)(const std::filesystem::path&);
  VolumeData (*region)(const std::filesystem::path&, const VoxelBox&, int frame);
};

std::span<const VolumeFormat> volume_formats_table();

// The row for `probe`, nullptr when no volume format takes it; `wrapped` as find_format sets it.
const VolumeFormat* find_volume_format(const FileProbe& probe, bool* wrapped = nullptr);

}  // namespace imx::detail
