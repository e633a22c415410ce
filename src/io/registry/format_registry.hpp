// The format registry: one table per kind of file (volumes, meshes, surface overlays,
// transforms, label tables), each row naming a format, how it is known (extensions, content),
// how it is read and written, its fuzz target and the reader it is checked against. Reading,
// the is_*_file tests, error messages, `intermix info --formats`, scripts/fuzz's seeds and the
// README's format table all come from the rows (docs/architecture.md, "Adding a format").
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace imx::detail {

enum class FileKind : uint8_t {
  volume,
  mesh,
  overlay,
  transform,
  label_table,
  streamlines,
  connectome
};

// "volume", "mesh", "surface overlay", "transform", "label table", "streamlines", "connectome".
const char* file_kind_name(FileKind kind);

// What reading knows of a file before choosing its format: the name and the first bytes.
struct FileProbe {
  std::filesystem::path path;
  std::string name;     // the file name in lower case
  std::string head;     // the first kProbeBytes bytes, inflated when the file is gzip data
  bool folder = false;  // a folder (DICOM)
};
inline constexpr size_t kProbeBytes = 512;

// Reads what FileProbe needs; a file that cannot be read leaves `head` empty (the reader says why).
FileProbe probe_file(const std::filesystem::path& file);
// A probe from a name alone (no bytes): for is_*_file tests of names that may not exist.
FileProbe probe_name(const std::filesystem::path& file);

// What every row says besides its readers.
struct FormatInfo {
  FileKind kind = FileKind::volume;
  std::string_view name = {};                     // "NIfTI-1/2 and Analyze 7.5"
  std::vector<std::string_view> extensions = {};  // lower case, compound ones whole (".nii.gz")
  // True when the file's first bytes (or, for folders, the path) are this format's, whatever
  // its name: a magic number, a first line. nullptr: known by extension only.
  bool (*sniff)(const FileProbe& probe) = nullptr;
  std::string_view writes = {};       // extensions written, "" when there is no writer
  std::string_view fuzz_target = {};  // fuzz/<target>.cpp reaches the reader
  std::string_view fuzz_seeds = {};   // find(1) name patterns of seed files for that target
  std::string_view reference = {};    // the reader every file is checked against
  std::string_view needs = {};        // what a file of this format needs beside it, "" when none
  // Extensions whose gzip (name + ".gz") is read by inflating it first, with the budget's bound:
  // files that stand alone (an attached .nrrd, not a detached .nhdr naming its data file).
  std::vector<std::string_view> gz_wrapped = {};
};

// The extension of `row` that `name` (lower case) ends with, longest first; "" when none.
std::string_view matched_extension(const FormatInfo& row, std::string_view name);

// The row of `rows` for `probe`: the first whose sniff accepts the bytes, else the one with the
// longest extension that ends the name, else (for a .gz of a gz_wrapped extension) that row with
// `*wrapped` set. nullopt when none.
template <class Row>
const Row* find_format(std::span<const Row> rows, const FileProbe& probe, bool* wrapped = nullptr);

// The suffix an unknown file is named by: the last extension, with the one before when the
// last is a compression (".trk.gz", ".nii.bz2"); a FreeSurfer-style name (lh.pial) gives ".pial".
std::string compound_suffix(const std::filesystem::path& file);

// "NRRD (.nrrd .nhdr), ..., MZ3 values (by content)": each row's name and extensions (with
// their .gz for rows that take one), for messages.
std::string list_formats(std::span<const FormatInfo* const> rows);

}  // namespace imx::detail

#include "io/registry/format_registry_impl.hpp"
