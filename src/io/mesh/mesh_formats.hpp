// The mesh formats' table of the format registry: read_mesh_file chooses its reader here.
#pragma once
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "intermix/io.hpp"
#include "io/registry/format_registry.hpp"

namespace imx::detail {

// What a mesh reader gives read_mesh_file, which then checks, places and completes it.
struct MeshContent {
  Mesh mesh;
  std::vector<MeshPointData> point_data;
  std::optional<MeshSpace> space;  // the space the file's header names, if any
  std::vector<std::string> notes;
};

struct MeshFormat {
  FormatInfo info;
  MeshContent (*read)(const std::filesystem::path&);
  MeshSpace native_space;  // the format's own space when the header names none
};

std::span<const MeshFormat> mesh_formats_table();

// The row for `probe`, nullptr when no mesh format takes it; `wrapped` as find_format sets it.
const MeshFormat* find_mesh_format(const FileProbe& probe, bool* wrapped = nullptr);

}  // namespace imx::detail
