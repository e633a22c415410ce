// The streamline (tractogram) and connectome formats' tables of the format registry.
#pragma once
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "intermix/streamlines.hpp"
#include "io/registry/format_registry.hpp"

namespace imx::detail {

struct StreamlineFormat {
  FormatInfo info;
  // The streamlines of a file; nullptr for values that belong to a tractogram given before.
  Streamlines (*read)(const std::filesystem::path&, std::vector<std::string>& notes) = nullptr;
  // Per-point values of the tractogram `tracks` (read from that file), appended to it.
  void (*read_values)(const std::filesystem::path&, Streamlines& tracks,
                      std::vector<std::string>& notes,
                      const std::filesystem::path& tracks_file) = nullptr;
};

struct ConnectomeFormat {
  FormatInfo info;
  Connectome (*read)(const std::filesystem::path&, std::vector<std::string>& notes) = nullptr;
};

std::span<const StreamlineFormat> streamline_formats_table();
std::span<const ConnectomeFormat> connectome_formats_table();

const StreamlineFormat* find_streamline_format(const FileProbe& probe);
const ConnectomeFormat* find_connectome_format(const FileProbe& probe);

// Whether `file` is a tractogram (or its values), or a connectome.
bool is_streamline_file(const std::filesystem::path& file);
bool is_connectome_file(const std::filesystem::path& file);

// The streamlines of `file`, a .gz of a format that allows one inflated first, then the
// per-point values of each of `values` (TSF files) appended. Errors name the file at fault.
Streamlines read_streamline_file(const std::filesystem::path& file,
                                 const std::vector<std::filesystem::path>& values,
                                 std::vector<std::string>& notes);

Connectome read_connectome_file(const std::filesystem::path& file, std::vector<std::string>& notes);

}  // namespace imx::detail
