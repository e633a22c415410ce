// One row per streamline and connectome format. A new format: its reader file and one row here
// (docs/architecture.md).
#include "io/streamlines/streamline_formats.hpp"

#include <algorithm>
#include <array>
#include <fstream>
#include <regex>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/connectome/brainnet.hpp"
#include "io/connectome/jcon.hpp"
#include "io/streamlines/tck.hpp"
#include "io/streamlines/trk.hpp"
#include "io/streamlines/trx.hpp"
#include "io/streamlines/tt.hpp"
#include "io/streamlines/vtk_streamlines.hpp"
#include "io/streams/inflated_file.hpp"
#include "io/streams/input_file.hpp"

namespace imx::detail {
namespace {

bool trk_head(const FileProbe& probe) {
  return probe.head.starts_with("TRACK");
}
bool tck_head(const FileProbe& probe) {
  return probe.head.starts_with("mrtrix tracks");
}
bool tsf_head(const FileProbe& probe) {
  return probe.head.starts_with("mrtrix track scalars");
}

// VTK polydata whose cells are lines and nothing else: a tractogram, not a mesh. Legacy files
// are scanned in pieces for their section keywords (ASCII even in BINARY files); an XML file's
// Piece element gives its cell counts.
bool vtk_lines_only(const FileProbe& probe) {
  if (probe.folder) return false;
  if (probe.head.starts_with("# vtk DataFile")) {
    std::ifstream in = try_open_input_stream(probe.path);
    std::string carry, chunk(1 << 20, '\0');
    bool lines = false;
    while (in) {
      in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
      std::string text = carry + chunk.substr(0, static_cast<size_t>(in.gcount()));
      for (const char* surface : {"\nPOLYGONS ", "\nTRIANGLE_STRIPS "})
        if (text.find(surface) != std::string::npos) return false;
      lines = lines || text.find("\nLINES ") != std::string::npos;
      carry = text.substr(text.size() - std::min<size_t>(text.size(), 20));
    }
    return lines;
  }
  if (!probe.name.ends_with(".vtp")) return false;
  std::ifstream in = try_open_input_stream(probe.path);
  std::string text(4096, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<size_t>(in.gcount()));
  const auto count = [&text](const char* attribute) {
    std::smatch m;
    const std::regex pattern(std::string(attribute) + "=\"\\s*(\\d+)\\s*\"");
    return std::regex_search(text, m, pattern) ? std::stoull(m[1].str().substr(0, 18)) : 0ull;
  };
  return count("NumberOfLines") > 0 && count("NumberOfPolys") == 0 && count("NumberOfStrips") == 0;
}

bool connectome_json(const FileProbe& probe) {
  return probe.name.ends_with(".json") && looks_like_connectome_json(probe.head);
}

Connectome brainnet_nodes(const std::filesystem::path& file, std::vector<std::string>& notes) {
  return read_brainnet(file, std::nullopt, notes);
}

}  // namespace

std::span<const StreamlineFormat> streamline_formats_table() {
  static const std::vector<StreamlineFormat> table = {
      {{.kind = FileKind::streamlines,
        .name = "TrackVis",
        .extensions = {".trk"},
        .sniff = trk_head,
        .fuzz_target = "fuzz_trk",
        .fuzz_seeds = "*.trk",
        .reference = "nibabel.streamlines (TrkFile)",
        .gz_wrapped = {".trk"}},
       read_trk},
      {{.kind = FileKind::streamlines,
        .name = "MRtrix tracks",
        .extensions = {".tck"},
        .sniff = tck_head,
        .fuzz_target = "fuzz_tck",
        .fuzz_seeds = "*.tck",
        .reference = "nibabel.streamlines (TckFile)",
        .gz_wrapped = {".tck"}},
       read_tck},
      {{.kind = FileKind::streamlines,
        .name = "MRtrix track scalars",
        .extensions = {".tsf"},
        .sniff = tsf_head,
        .fuzz_target = "fuzz_tck",
        .fuzz_seeds = "*.tsf",
        .reference = "MRtrix's layout (values split at NaN, as the .tck)",
        .needs = "the .tck tractogram it belongs to, given before it"},
       nullptr,
       read_tsf},
      {{.kind = FileKind::streamlines,
        .name = "TRX",
        .extensions = {".trx"},
        .fuzz_target = "fuzz_trx",
        .fuzz_seeds = "*.trx",
        .reference = "the TRX specification, trx-python's rules"},
       read_trx},
      {{.kind = FileKind::streamlines,
        .name = "DSI Studio TinyTrack",
        .extensions = {".tt.gz", ".tt"},
        .fuzz_target = "fuzz_tt",
        .fuzz_seeds = "*.tt*",
        .reference = "DSI Studio's layout, as NiiVue reads it"},
       read_tt},
      {{.kind = FileKind::streamlines,
        .name = "VTK polylines",
        .sniff = vtk_lines_only,
        .fuzz_target = "fuzz_vtk_streamlines",
        .fuzz_seeds = "*.vtk *.vtp",
        .reference = "VTK 9.1's vtkPolyDataReader and vtkXMLPolyDataReader"},
       read_vtk_streamlines},
  };
  return table;
}

std::span<const ConnectomeFormat> connectome_formats_table() {
  static const std::vector<ConnectomeFormat> table = {
      {{.kind = FileKind::connectome,
        .name = "NiiVue connectome",
        .extensions = {".jcon"},
        .sniff = connectome_json,
        .fuzz_target = "fuzz_connectome",
        .fuzz_seeds = "*.jcon",
        .reference = "NiiVue's connectome loader"},
       read_jcon},
      {{.kind = FileKind::connectome,
        .name = "BrainNet Viewer nodes (and the .edge beside them)",
        .extensions = {".node"},
        .fuzz_target = "fuzz_connectome",
        .fuzz_seeds = "*.node",
        .reference = "BrainNet Viewer's layout"},
       brainnet_nodes},
      {{.kind = FileKind::connectome,
        .name = "BrainNet Viewer edges",
        .extensions = {".edge"},
        .fuzz_target = "fuzz_connectome",
        .fuzz_seeds = "*.edge",
        .reference = "BrainNet Viewer's layout",
        .needs = "its .node file: give the .node (the .edge of the same name beside it is read)"},
       nullptr},
  };
  return table;
}

const StreamlineFormat* find_streamline_format(const FileProbe& probe) {
  return find_format(streamline_formats_table(), probe);
}

const ConnectomeFormat* find_connectome_format(const FileProbe& probe) {
  return find_format(connectome_formats_table(), probe);
}

bool is_streamline_file(const std::filesystem::path& file) {
  return find_streamline_format(probe_file(file)) != nullptr;
}

bool is_connectome_file(const std::filesystem::path& file) {
  return find_connectome_format(probe_file(file)) != nullptr;
}

Streamlines read_streamline_file(const std::filesystem::path& file,
                                 const std::vector<std::filesystem::path>& values,
                                 std::vector<std::string>& notes) {
  bool wrapped = false;
  const StreamlineFormat* format =
      find_format(streamline_formats_table(), probe_file(file), &wrapped);
  if (!format) {
    std::vector<const FormatInfo*> rows;
    for (const StreamlineFormat& f : streamline_formats_table()) rows.push_back(&f.info);
    throw Error(fmt::format("{}: '{}' is not a tractogram format intermix reads ({})",
                            file.string(), compound_suffix(file), list_formats(rows)));
  }
  if (!format->read)
    throw Error(fmt::format("{}: {} is {}: it needs {}", file.string(), file.filename().string(),
                            format->info.name, format->info.needs));
  const auto read = [&](const std::filesystem::path& path) { return format->read(path, notes); };
  Streamlines s = wrapped ? read_inflated(file, input_limits().max_memory, read) : read(file);
  for (const std::filesystem::path& v : values) {
    const StreamlineFormat* of = find_streamline_format(probe_file(v));
    if (!of || !of->read_values)
      throw Error(fmt::format("{}: not per-point values of a tractogram (a .tsf)", v.string()));
    of->read_values(v, s, notes, file);
  }
  return s;
}

Connectome read_connectome_file(const std::filesystem::path& file,
                                std::vector<std::string>& notes) {
  const ConnectomeFormat* format = find_connectome_format(probe_file(file));
  if (!format) throw Error(fmt::format("{}: not a connectome intermix reads", file.string()));
  if (!format->read)
    throw Error(fmt::format("{}: {} is {}: it needs {}", file.string(), file.filename().string(),
                            format->info.name, format->info.needs));
  return format->read(file, notes);
}

}  // namespace imx::detail
