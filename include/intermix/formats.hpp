// The file formats intermix reads and writes, from its format registry: what `intermix info
// --formats` prints and the README's format table.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace imx {

struct FileFormat {
  std::string kind;                        // "volume", "mesh", "surface overlay", "transform", ...
  std::string name;                        // "NIfTI-1/2, Analyze 7.5"
  std::vector<std::string> extensions;     // ".nii", ".nii.gz", ...; empty: known by content only
  bool by_content = false;                 // known by its first bytes too, whatever its name
  std::vector<std::string> gz_extensions;  // ".obj.gz", ...: gzipped files read by inflating
  std::string writes;                      // extensions written, "" when none
  std::string reference;                   // the reader it is checked against
  std::string needs;                       // what a file of it needs beside it, "" when none
  std::string fuzz_target;                 // the libFuzzer target that reaches its reader
  std::string fuzz_seeds;                  // find(1) patterns of that target's seed files
};

// Every row of every kind's table, kind by kind.
std::vector<FileFormat> file_formats();

// The formats as a Markdown table (the README's "File formats" table).
std::string file_formats_markdown();

// What a file given on its own (`intermix render FILE...`, `intermix info FILE`) is: its kind's
// name and format, by content and name. Throws imx::Error naming the file and its whole suffix
// with the formats of every kind when it is none of them, and saying what a file that cannot
// stand alone needs ("lh.curv is a surface overlay: give it after its surface ...").
struct IdentifiedFile {
  std::string kind;
  std::string format;
  std::string needs;  // what it needs beside it ("" for volumes and meshes, which stand alone)
};
IdentifiedFile identify_file(const std::filesystem::path& file);

// "lh.curv is a surface overlay (FreeSurfer morphometry): give it after its surface (intermix
// render lh.pial lh.curv)": for a file that cannot stand alone.
std::string needs_message(const std::filesystem::path& file, const IdentifiedFile& identified);

// The error identify_file throws for a file of no known format: for callers that know the file
// is not a scene file either.
std::string unknown_format_message(const std::filesystem::path& file);

}  // namespace imx
