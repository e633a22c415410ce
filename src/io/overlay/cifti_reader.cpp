#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <system_error>
#include <variant>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/overlay/cifti.hpp"
#include "io/overlay/cifti_xml.hpp"
#include "io/streams/file_head.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/regular_file.hpp"
#include "io/voxels/frame_voxels.hpp"
#include "io/voxels/nifti_header.hpp"

namespace imx::detail {
namespace {

constexpr const char* kStructurePrefix = "CIFTI_STRUCTURE_";
constexpr int kCiftiExtensionCode = 32;
constexpr uint64_t kNifti2HeaderBytes = 540;

bool cifti_intent(int code) {
  return code >= 3000 && code <= 3099;
}

std::string map_word(CiftiMapKind kind) {
  return kind == CiftiMapKind::series ? "frame" : "map";
}

// The header extensions' CIFTI-2 XML (ecode 32), from the bytes before the data.
std::string cifti_extension(const std::string& head, const NiftiHeader& h,
                            const std::string& what) {
  if (head.size() < kNifti2HeaderBytes + 4 || head[kNifti2HeaderBytes] == 0)
    throw Error(
        fmt::format("{}: its intent ({}) is CIFTI's, but it has no header extension "
                    "(where CIFTI-2 keeps its XML)",
                    what, h.intent_code));
  uint64_t at = kNifti2HeaderBytes + 4;
  while (at + 8 <= h.vox_offset) {
    int32_t field[2];
    std::memcpy(field, head.data() + at, sizeof field);
    if (h.swapped)
      for (int32_t& f : field)
        f = static_cast<int32_t>(__builtin_bswap32(static_cast<uint32_t>(f)));
    const int32_t esize = field[0], ecode = field[1];
    if (esize < 8 || at + static_cast<uint64_t>(esize) > h.vox_offset)
      throw Error(
          fmt::format("{}: the header extension at byte {} has esize {}, which does not "
                      "fit between its start and the data (vox_offset {})",
                      what, at, esize, h.vox_offset));
    if (ecode == kCiftiExtensionCode) {
      std::string_view xml(head.data() + at + 8, static_cast<size_t>(esize) - 8);
      while (!xml.empty() && xml.back() == '\0') xml.remove_suffix(1);  // padding to 16 bytes
      return std::string(xml);
    }
    at += static_cast<uint64_t>(esize);
  }
  throw Error(
      fmt::format("{}: its intent ({}) is CIFTI's, but no header extension holds CIFTI "
                  "XML (ecode 32)",
                  what, h.intent_code));
}

// The surface model named `structure` (with or without the prefix, any case), or nullptr.
const CiftiBrainModel* find_surface(const CiftiFile& c, const std::string& structure) {
  std::string want = lower(structure);
  if (!want.starts_with(lower(kStructurePrefix))) want = lower(kStructurePrefix) + want;
  for (const CiftiBrainModel& m : c.models)
    if (m.surface && lower(m.structure) == want) return &m;
  return nullptr;
}

std::string surface_list(const CiftiFile& c) {
  std::vector<std::string> names;
  for (const CiftiBrainModel& m : c.models)
    if (m.surface)
      names.push_back(
          fmt::format("{} ({} vertices)", short_structure_name(m.structure), m.surface_vertices));
  return names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", "));
}

// The brain models in order, tiling 0..N-1, each surface model's vertices existing and distinct.
int64_t check_models(std::vector<CiftiBrainModel>& models, const std::string& what) {
  std::stable_sort(
      models.begin(), models.end(),
      [](const CiftiBrainModel& a, const CiftiBrainModel& b) { return a.offset < b.offset; });
  int64_t next = 0, claimed = 0;
  for (const CiftiBrainModel& m : models) {
    const std::string name = short_structure_name(m.structure);
    if (m.count < 1 || m.count > kMaxCiftiBrainordinates)
      throw Error(fmt::format("{}: brain model {} has IndexCount {}; 1 to {} expected", what, name,
                              m.count, kMaxCiftiBrainordinates));
    if (m.offset != next)
      throw Error(
          fmt::format("{}: brain model {} has IndexOffset {}, but the models before it end "
                      "at {}: the models must cover the brainordinates one after another",
                      what, name, m.offset, next));
    next += m.count;
    if (next > kMaxCiftiBrainordinates)
      throw Error(fmt::format("{}: the brain models claim more than {} brainordinates", what,
                              kMaxCiftiBrainordinates));
    if (!m.surface) continue;
    if (m.surface_vertices < 1 || m.surface_vertices > kMaxCiftiBrainordinates)
      throw Error(fmt::format("{}: brain model {} has SurfaceNumberOfVertices {}; 1 to {} expected",
                              what, name, m.surface_vertices, kMaxCiftiBrainordinates));
    // Every surface's vertices are allocated in turn: their sum is held to the bound too.
    claimed += m.surface_vertices;
    if (claimed > kMaxCiftiBrainordinates)
      throw Error(fmt::format("{}: the surface models claim more than {} vertices in all", what,
                              kMaxCiftiBrainordinates));
    if (static_cast<int64_t>(m.vertices.size()) != m.count)
      throw Error(fmt::format("{}: brain model {} has IndexCount {} but {} VertexIndices", what,
                              name, m.count, m.vertices.size()));
    std::vector<bool> seen(static_cast<size_t>(m.surface_vertices), false);
    for (uint32_t v : m.vertices) {
      if (v >= m.surface_vertices)
        throw Error(
            fmt::format("{}: brain model {} lists vertex {}, but its surface has "
                        "SurfaceNumberOfVertices {}",
                        what, name, v, m.surface_vertices));
      if (seen[v])
        throw Error(fmt::format("{}: brain model {} lists vertex {} twice", what, name, v));
      seen[v] = true;
    }
  }
  return next;
}

// What the NIfTI-2 header of a CIFTI-2 file must say: a CIFTI intent, dim[1] to dim[4] at 1, the
// matrix along dim[5] and dim[6], a bounded XML extension before the data.
void check_cifti_nifti_header(const NiftiHeader& h, const std::string& what) {
  if (!cifti_intent(h.intent_code))
    throw Error(fmt::format("{}: not a CIFTI file (NIfTI intent code {}, CIFTI's are 3000-3099)",
                            what, h.intent_code));
  if (h.kind != NiftiKind::nifti2)
    throw Error(fmt::format("{}: a {} file with a CIFTI intent ({}); CIFTI-2 files are NIfTI-2",
                            what, nifti_kind_name(h.kind), h.intent_code));
  for (int d = 1; d <= 4; ++d)
    if (h.dim[d] != 1)
      throw Error(
          fmt::format("{}: dim[{}] is {}; a CIFTI-2 file keeps dim[1] to dim[4] at 1 "
                      "(its matrix lies along dim[5] and dim[6])",
                      what, d, h.dim[d]));
  if (h.ndim > 6)
    throw Error(
        fmt::format("{}: dim[0] is {}; intermix reads CIFTI-2 matrices of two "
                    "dimensions (dim[0] 5 or 6)",
                    what, h.ndim));
  if (h.vox_offset > kMaxCiftiXmlBytes)
    throw Error(fmt::format("{}: vox_offset is {}: more than {} bytes of header extensions", what,
                            h.vox_offset, kMaxCiftiXmlBytes));
}

// The two index maps of a dense file: brain models along one matrix dimension, the maps
// (scalars, labels or series) along the other.
struct DenseIndexMaps {
  const CiftiIndexMap* maps = nullptr;
  CiftiIndexMap* models = nullptr;
  bool maps_fastest = true;  // the brain models along matrix dimension 1
};

DenseIndexMaps dense_index_maps(CiftiXml& xml, const std::string& what) {
  CiftiIndexMap* along[2] = {nullptr, nullptr};
  for (CiftiIndexMap& m : xml.maps) {
    if (m.type == "CIFTI_INDEX_TYPE_PARCELS")
      throw Error(
          fmt::format("{}: a parcellated CIFTI-2 file (CIFTI_INDEX_TYPE_PARCELS: "
                      ".pscalar, .ptseries, .pconn...); intermix reads dense files, "
                      "whose values belong to vertices (.dscalar, .dlabel, .dtseries)",
                      what));
    for (int d : m.dimensions) {
      if (along[d])
        throw Error(fmt::format("{}: two index maps apply to matrix dimension {}", what, d));
      along[d] = &m;
    }
  }
  for (int d = 0; d < 2; ++d)
    if (!along[d])
      throw Error(fmt::format("{}: no index map applies to matrix dimension {}", what, d));
  const bool models0 = along[0]->type == "CIFTI_INDEX_TYPE_BRAIN_MODELS";
  const bool models1 = along[1]->type == "CIFTI_INDEX_TYPE_BRAIN_MODELS";
  if (models0 && models1)
    throw Error(
        fmt::format("{}: dense connectivity (brain models along both dimensions, "
                    ".dconn); intermix reads maps of values on vertices (.dscalar, "
                    ".dlabel, .dtseries)",
                    what));
  if (!models0 && !models1)
    throw Error(
        fmt::format("{}: no CIFTI_INDEX_TYPE_BRAIN_MODELS map (maps {} and {}): no "
                    "values on vertices",
                    what, along[0]->type, along[1]->type));
  return {along[models1 ? 0 : 1], along[models1 ? 1 : 0], models1};
}

}  // namespace

std::string short_structure_name(const std::string& structure) {
  return structure.starts_with(kStructurePrefix)
             ? structure.substr(std::string_view(kStructurePrefix).size())
             : structure;
}

bool is_cifti_head(std::string_view head) {
  auto field = [&](size_t at, auto zero, bool swapped) {
    decltype(zero) v;
    std::memcpy(&v, head.data() + at, sizeof v);
    if (swapped) {
      char* b = reinterpret_cast<char*>(&v);
      std::reverse(b, b + sizeof v);
    }
    return v;
  };
  if (head.size() < 348) return false;
  for (bool swapped : {false, true}) {
    const int32_t size = field(0, int32_t{}, swapped);
    if (size == 540 && head.size() >= 508 && head.substr(4, 4) == std::string_view("n+2\0", 4))
      return cifti_intent(field(504, int32_t{}, swapped));
    if (size == 348 && (head.substr(344, 4) == std::string_view("n+1\0", 4) ||
                        head.substr(344, 4) == std::string_view("ni1\0", 4)))
      return cifti_intent(field(68, int16_t{}, swapped));
  }
  return false;
}

bool is_cifti(const std::filesystem::path& file) {
  try {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) return false;
    return is_cifti_head(read_file_head(file, 512, file.string()).bytes);
  } catch (const std::exception&) {
    return false;
  }
}

VertexOverlay read_cifti_vertex_overlay(const std::filesystem::path& file, int map) {
  const CiftiFile c = read_cifti(file);
  std::vector<const CiftiBrainModel*> surfaces;
  for (const CiftiBrainModel& m : c.models)
    if (m.surface) surfaces.push_back(&m);
  if (surfaces.size() != 1)
    throw Error(
        fmt::format("{}: its surface structures are {}: which one a surface shows is "
                    "chosen with the surface (give the file after it, or the overlay's "
                    "\"structure\")",
                    file.string(), surface_list(c)));
  return cifti_overlay(c, surfaces[0]->structure, std::max(map, 0), file.string());
}

CiftiFile read_cifti(const std::filesystem::path& file) {
  const std::string what = file.string();
  require_regular_file(file);
  const FileHead first = read_file_head(file, kNifti2HeaderBytes, what);
  const NiftiHeader h = decode_nifti_header(first.bytes, false, first.gzipped, what);
  check_cifti_nifti_header(h, what);
  std::error_code ec;
  const uintmax_t file_size = std::filesystem::file_size(file, ec);
  if (!first.gzipped && !ec && h.vox_offset > file_size)
    throw Error(fmt::format("{}: vox_offset is {}, past the file's end ({} bytes)", what,
                            h.vox_offset, file_size));
  const FileHead head = read_file_head(file, static_cast<size_t>(h.vox_offset), what);
  if (head.bytes.size() < h.vox_offset)
    throw Error(fmt::format("{}: the file ends at byte {}, before its data (vox_offset {})", what,
                            head.bytes.size(), h.vox_offset));

  CiftiXml xml = parse_cifti_xml(cifti_extension(head.bytes, h, what), what);
  if (xml.version.starts_with("1"))
    throw Error(
        fmt::format("{}: CIFTI version {}; intermix reads CIFTI-2 (wb_command "
                    "-file-convert -cifti-version-convert converts it)",
                    what, shown(xml.version)));
  if (!xml.version.starts_with("2"))
    throw Error(
        fmt::format("{}: the CIFTI element's Version is '{}', not 2", what, shown(xml.version)));

  DenseIndexMaps dense = dense_index_maps(xml, what);
  CiftiFile c;
  c.file = file;
  c.intent_code = h.intent_code;
  c.maps_fastest = dense.maps_fastest;
  const CiftiIndexMap& maps = *dense.maps;
  CiftiIndexMap& models = *dense.models;
  if (maps.type == "CIFTI_INDEX_TYPE_SCALARS" || maps.type == "CIFTI_INDEX_TYPE_LABELS") {
    c.kind = maps.type == "CIFTI_INDEX_TYPE_LABELS" ? CiftiMapKind::labels : CiftiMapKind::scalars;
    c.maps = static_cast<int64_t>(maps.names.size());
    c.map_names = maps.names;
    if (c.kind == CiftiMapKind::labels) c.label_tables = maps.tables;
  } else if (maps.type == "CIFTI_INDEX_TYPE_SERIES") {
    c.kind = CiftiMapKind::series;
    c.maps = maps.series_points;
  } else {
    throw Error(
        fmt::format("{}: an index map of {}; intermix reads scalars, labels and series "
                    "beside the brain models",
                    what, shown(maps.type)));
  }
  if (c.maps < 1 || c.maps > kMaxCiftiMaps)
    throw Error(
        fmt::format("{}: {} {}s; 1 to {} expected", what, c.maps, map_word(c.kind), kMaxCiftiMaps));
  c.brainordinates = check_models(models.models, what);
  c.models = std::move(models.models);

  // The NIfTI dims must be the XML's: maps x brainordinates (or the transpose).
  const int64_t rows = h.dim[5], columns = h.ndim >= 6 ? h.dim[6] : 1;
  const int64_t want_rows = c.maps_fastest ? c.maps : c.brainordinates;
  const int64_t want_columns = c.maps_fastest ? c.brainordinates : c.maps;
  if (rows != want_rows || columns != want_columns)
    throw Error(
        fmt::format("{}: the data is {} x {} (dim[5] x dim[6]), but the XML gives {} "
                    "{}s x {} brainordinates",
                    what, rows, columns, c.maps, map_word(c.kind), c.brainordinates));
  if (static_cast<double>(c.maps) * static_cast<double>(c.brainordinates) >
      static_cast<double>(kMaxVoxels))
    throw Error(fmt::format("{}: {} {}s of {} brainordinates are more than {} values", what, c.maps,
                            map_word(c.kind), c.brainordinates, kMaxVoxels));
  c.type = h.type;
  c.swap = h.swapped;
  c.gzipped = first.gzipped;
  c.offset = h.vox_offset;
  c.slope = h.slope;
  c.inter = h.inter;
  const uint64_t data_bytes = static_cast<uint64_t>(c.maps) *
                              static_cast<uint64_t>(c.brainordinates) * raw_type_size(c.type);
  if (!c.gzipped && !ec && file_size - h.vox_offset < data_bytes)
    throw Error(fmt::format("{}: expected {} bytes of data after vox_offset {}, found {}", what,
                            data_bytes, h.vox_offset, file_size - h.vox_offset));
  return c;
}

VertexOverlay cifti_overlay(const CiftiFile& c, const std::string& structure, int64_t map,
                            const std::string& what) {
  const CiftiBrainModel* model = find_surface(c, structure);
  if (!model)
    throw Error(fmt::format("{}: no surface structure {} (its surface structures: {})", what,
                            short_structure_name(structure), surface_list(c)));
  if (map < 0 || map >= c.maps)
    throw Error(fmt::format("{}: {} {} asked for; it has {} {}s (0 to {})", what, map_word(c.kind),
                            map, c.maps, map_word(c.kind), c.maps - 1));
  FrameLayout layout;
  layout.file = c.file;
  layout.what = what;
  layout.gzipped = c.gzipped;
  layout.offset = c.offset;
  layout.type = c.type;
  layout.swap = c.swap;
  const int m = static_cast<int>(map), first = static_cast<int>(model->offset),
            count = static_cast<int>(model->count);
  VoxelBox box;
  if (c.maps_fastest) {
    layout.dims = glm::ivec3(static_cast<int>(c.maps), static_cast<int>(c.brainordinates), 1);
    box = {{m, first, 0}, {m + 1, first + count, 1}};
  } else {
    layout.dims = glm::ivec3(static_cast<int>(c.brainordinates), static_cast<int>(c.maps), 1);
    box = {{first, m, 0}, {first + count, m + 1, 1}};
  }
  layout.frames = 1;
  const VoxelStorage data = read_frame_voxels(layout, 0, box);

  VertexOverlay out;
  out.claimed_vertices = static_cast<uint64_t>(model->surface_vertices);
  // A surface's vertex count is a claim the data need not back (the medial wall has none).
  check_memory(out.claimed_vertices * sizeof(double), what);
  out.values.assign(static_cast<size_t>(model->surface_vertices),
                    std::numeric_limits<double>::quiet_NaN());
  const bool scaled = c.slope != 0.0;
  std::visit(
      [&](const auto& buffer) {
        for (size_t i = 0; i < model->vertices.size(); ++i) {
          const double v = static_cast<double>(buffer[i]);
          out.values[model->vertices[i]] = scaled ? v * c.slope + c.inter : v;
        }
      },
      data);
  if (c.kind == CiftiMapKind::labels) {
    out.labels = true;
    out.table = c.label_tables[static_cast<size_t>(map)];
  }
  return out;
}

}  // namespace imx::detail
