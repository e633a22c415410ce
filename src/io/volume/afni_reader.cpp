// AFNI's BRIK/HEAD datasets (https://afni.nimh.nih.gov/pub/dist/doc/program_help/
// README.attributes.html), read as nibabel.brikhead reads them, nibabel being the reference the
// tests compare to.
#include <cmath>
#include <cstdint>
#include <fstream>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streams/file_head.hpp"
#include "io/streams/gzip.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/inflate_charge.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"
#include "io/volume/afni.hpp"
#include "io/volume/afni_attributes.hpp"
#include "io/voxels/frame_voxels.hpp"
#include "io/voxels/frames.hpp"
#include "io/voxels/raw_voxels.hpp"
#include "volume/volume_checks.hpp"

namespace imx::detail {

namespace fs = std::filesystem;

namespace {

// HEAD files hold a few kB of attributes, more with a long HISTORY_NOTE; far beyond is not one.
constexpr uintmax_t kMaxHeadBytes = uintmax_t{16} << 20;

// AFNI's TAXIS_NUMS[2] unit codes.
constexpr int kUnitsMsec = 77001, kUnitsSec = 77002;

bool ends_with_lower(const std::string& name, std::string_view suffix) {
  return name.size() >= suffix.size() && lower(name.substr(name.size() - suffix.size())) == suffix;
}

struct AfniFiles {
  fs::path head, brik;
  std::string what;       // the name given, for messages about the header
  std::string data_what;  // "X.BRIK (voxel data of X.HEAD)"
};

// The HEAD and BRIK of the dataset named by either: X.HEAD, X.BRIK or X.BRIK.gz. From a HEAD,
// X.BRIK is looked for first, then X.BRIK.gz, as nibabel looks.
AfniFiles afni_files(const fs::path& given) {
  AfniFiles f;
  f.what = given.string();
  const std::string name = given.filename().string();
  const fs::path dir = given.parent_path();
  auto sibling = [&](size_t stem_length, std::string_view ext) {
    return dir / (name.substr(0, stem_length) + std::string(ext));
  };
  for (const char* packed : {".brik.bz2", ".brik.z", ".brik.zst"})
    if (ends_with_lower(name, packed))
      throw Error(
          fmt::format("{}: this compression of a BRIK is not supported (only gzip: "
                      ".BRIK.gz)",
                      f.what));
  if (ends_with_lower(name, ".head")) {
    const size_t stem = name.size() - 5;
    const bool upper = name[stem + 1] == 'H';
    f.head = given;
    require_regular_file(given, f.what);  // the HEAD named is checked before its BRIK is looked for
    const fs::path plain = sibling(stem, upper ? ".BRIK" : ".brik");
    f.brik = plain;
    if (!fs::exists(plain)) f.brik = sibling(stem, upper ? ".BRIK.gz" : ".brik.gz");
    if (!fs::exists(f.brik)) {
      for (const char* packed : {".bz2", ".Z", ".zst"})
        if (fs::exists(plain.string() + packed))
          throw Error(
              fmt::format("{}: its voxels are in {}{}, compressed as {}, which is not "
                          "supported (only gzip, .BRIK.gz)",
                          f.what, plain.string(), packed, packed + 1));
      throw FileError(fmt::format("{}: its voxel data is missing ({} or {}.gz looked for)", f.what,
                                  plain.string(), plain.filename().string()),
                      ENOENT);
    }
  } else {
    size_t stem = 0;
    if (ends_with_lower(name, ".brik"))
      stem = name.size() - 5;
    else if (ends_with_lower(name, ".brik.gz"))
      stem = name.size() - 8;
    else
      throw Error(
          fmt::format("{}: not an AFNI dataset name (X+orig.HEAD, X+orig.BRIK or "
                      "X+orig.BRIK.gz expected)",
                      f.what));
    const bool upper = name[stem + 1] == 'B';
    f.brik = given;
    f.head = sibling(stem, upper ? ".HEAD" : ".head");
    if (!fs::exists(f.head))
      throw FileError(fmt::format("{}: its header {} is missing", f.what, f.head.string()), ENOENT);
  }
  f.data_what = fmt::format("{} (voxel data of {})", f.brik.string(), f.head.string());
  return f;
}

std::string read_head_text(const AfniFiles& f) {
  const std::string what = f.head.string();
  require_regular_file(f.head, what);
  std::error_code ec;
  const uintmax_t size = fs::file_size(f.head, ec);
  if (ec) throw FileError(fmt::format("{}: cannot read its size: {}", what, ec.message()));
  if (size > kMaxHeadBytes)
    throw Error(fmt::format("{}: {} bytes, more than the {} an AFNI HEAD may hold", what, size,
                            kMaxHeadBytes));
  check_memory(size, what);
  std::ifstream in = open_input_stream(f.head, what);
  std::string text(static_cast<size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  if (static_cast<uintmax_t>(in.gcount()) != size)
    throw FileError(fmt::format("{}: cannot read the file", what), errno);
  if (text.size() >= 2 && static_cast<uint8_t>(text[0]) == 0x1f &&
      static_cast<uint8_t>(text[1]) == 0x8b)
    throw Error(
        fmt::format("{}: the HEAD is gzip-compressed; AFNI HEADs are plain text (only the "
                    "BRIK may be compressed)",
                    what));
  return text;
}

// The attributes read_afni uses, each of the kind it must have.
class Attributes {
 public:
  Attributes(AfniAttributes all, std::string what) : all_(std::move(all)), what_(std::move(what)) {}

  const AfniAttribute* find(std::string_view name, bool numeric) const {
    auto it = all_.find(name);
    if (it == all_.end()) return nullptr;
    if ((it->second.kind == AfniAttribute::Kind::string) == numeric)
      throw Error(fmt::format("{}: attribute {} is a {}, not a {}", what_, name,
                              numeric ? "string" : "number list",
                              numeric ? "number list" : "string"));
    return &it->second;
  }
  // A numeric attribute with at least `min_count` values, or nothing when absent.
  const std::vector<double>* numbers(std::string_view name, size_t min_count) const {
    const AfniAttribute* a = find(name, true);
    if (!a) return nullptr;
    if (a->numbers.size() < min_count)
      throw Error(fmt::format("{}: attribute {} has {} values, at least {} expected", what_, name,
                              a->numbers.size(), min_count));
    for (double v : a->numbers)
      if (!std::isfinite(v))
        throw Error(fmt::format("{}: attribute {} holds {}, not a finite number", what_, name, v));
    return &a->numbers;
  }
  const std::vector<double>& required(std::string_view name, size_t min_count) const {
    if (const std::vector<double>* v = numbers(name, min_count)) return *v;
    throw Error(fmt::format("{}: attribute {} is missing", what_, name));
  }
  const std::string* text(std::string_view name) const {
    const AfniAttribute* a = find(name, false);
    return a ? &a->text : nullptr;
  }
  const std::string& what() const { return what_; }

 private:
  AfniAttributes all_;
  std::string what_;
};

// BRICK_TYPES codes: 0 byte, 1 short, 2 int, 3 float, 4 double, 5 complex, 6 rgb. nibabel reads
// byte, short and float (and complex, which the renderer cannot show).
RawType brick_type(const Attributes& a) {
  const std::vector<double>& types = a.required("BRICK_TYPES", 1);
  for (double t : types)
    if (t != types.front()) {
      std::string list;
      for (double u : types) list += fmt::format(" {}", u);
      throw Error(
          fmt::format("{}: attribute BRICK_TYPES gives the sub-bricks different types "
                      "({} ); nibabel refuses such datasets, and so does intermix",
                      a.what(), list));
    }
  switch (static_cast<int>(types.front())) {
    case 0:
      return RawType::u8;
    case 1:
      return RawType::i16;
    case 3:
      return RawType::f32;
    case 5:
      throw Error(
          fmt::format("{}: BRICK_TYPES 5 (complex) is not supported: complex voxels have "
                      "no single value to render",
                      a.what()));
    default: {
      static const char* const names[] = {"byte",   "short",   "int", "float",
                                          "double", "complex", "rgb"};
      const double t = types.front();
      const std::string name = t >= 0 && t <= 6 ? names[static_cast<int>(t)] : "unknown";
      throw Error(
          fmt::format("{}: BRICK_TYPES {} ({}) is not supported (byte 0, short 1 and "
                      "float 3 are, as in nibabel)",
                      a.what(), t, name));
    }
  }
}

// Voxel to DICOM (RAI, which is LPS) mm: IJK_TO_DICOM_REAL's three rows, as nibabel takes them;
// without it, the cardinal axes of ORIENT_SPECIFIC with DELTA and ORIGIN, as AFNI builds them
// (THD_daxes_to_mat44): index axis i runs along DICOM axis ORIENT_SPECIFIC[i] / 2, DELTA
// carrying the direction's sign.
glm::dmat4 index_to_lps(const Attributes& a) {
  glm::dmat4 m(1.0);
  if (const std::vector<double>* real = a.numbers("IJK_TO_DICOM_REAL", 12)) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) m[c][r] = (*real)[4 * r + c];
    return m;
  }
  const std::vector<double>* orient = a.numbers("ORIENT_SPECIFIC", 3);
  const std::vector<double>* origin = a.numbers("ORIGIN", 3);
  const std::vector<double>* delta = a.numbers("DELTA", 3);
  if (!orient || !origin || !delta)
    throw Error(
        fmt::format("{}: neither IJK_TO_DICOM_REAL nor ORIENT_SPECIFIC, ORIGIN and DELTA "
                    "are given: the dataset cannot be placed",
                    a.what()));
  m = glm::dmat4(0.0);
  m[3][3] = 1.0;
  bool used[3] = {false, false, false};
  for (int axis = 0; axis < 3; ++axis) {
    const double code = (*orient)[axis];
    if (code < 0 || code > 5 || used[static_cast<int>(code) / 2])
      throw Error(
          fmt::format("{}: ORIENT_SPECIFIC {} {} {} does not name three different axes "
                      "(codes 0 to 5)",
                      a.what(), (*orient)[0], (*orient)[1], (*orient)[2]));
    const int row = static_cast<int>(code) / 2;
    used[row] = true;
    m[axis][row] = (*delta)[axis];
    m[3][row] = (*origin)[axis];
  }
  return m;
}

// One label per sub-brick: BRICK_LABS' '~'-separated names (nibabel's get_volume_labels) and,
// for a time series, the time of each (TAXIS_FLOATS[1] is the step, nibabel's fourth zoom).
std::vector<FrameLabel> frame_labels(const Attributes& a, int frames) {
  std::vector<std::string> names;
  if (const std::string* labs = a.text("BRICK_LABS")) {
    size_t at = 0;
    while (names.size() < static_cast<size_t>(frames)) {
      const size_t end = labs->find('~', at);
      names.push_back(labs->substr(at, end == std::string::npos ? std::string::npos : end - at));
      if (end == std::string::npos) break;
      at = end + 1;
    }
  }
  std::optional<double> step_s;
  const std::vector<double>* nums = a.numbers("TAXIS_NUMS", 3);
  const std::vector<double>* floats = a.numbers("TAXIS_FLOATS", 2);
  if (frames > 1 && nums && floats && (*floats)[1] > 0.0) {
    if ((*nums)[2] == kUnitsSec) step_s = (*floats)[1];
    if ((*nums)[2] == kUnitsMsec) step_s = (*floats)[1] / 1000.0;
  }
  std::vector<FrameLabel> labels;
  if (names.empty() && !step_s) return labels;
  labels.resize(static_cast<size_t>(frames));
  for (int k = 0; k < frames; ++k) {
    if (step_s) labels[k].time_s = k * *step_s;
    labels[k].text = static_cast<size_t>(k) < names.size() && !names[k].empty()
                         ? names[k]
                         : describe_frame(labels[k]);
  }
  return labels;
}

struct Layout {
  VolumeHeader header;
  FrameLayout data;
  std::vector<double> scales;  // one factor per sub-brick, or empty when unscaled
};

Layout parse_layout(const fs::path& file, bool labels) {
  const AfniFiles files = afni_files(file);
  const Attributes a(parse_afni_attributes(read_head_text(files), files.head.string()),
                     files.head.string());
  const std::string& what = a.what();

  const std::vector<double>& rank = a.required("DATASET_RANK", 2);
  if (rank[0] != 3)
    throw Error(
        fmt::format("{}: DATASET_RANK[0] is {}; AFNI sub-bricks are 3-D (3)", what, rank[0]));
  if (rank[1] < 1 || rank[1] > static_cast<double>(kMaxFrames))
    throw Error(fmt::format("{}: DATASET_RANK[1] gives {} sub-bricks; 1 to {} are read", what,
                            rank[1], kMaxFrames));
  const int frames = static_cast<int>(rank[1]);
  const std::vector<double>& d = a.required("DATASET_DIMENSIONS", 3);
  for (int k = 0; k < 3; ++k)
    if (d[k] < 1 || d[k] > static_cast<double>(kMaxVoxels))
      throw Error(
          fmt::format("{}: DATASET_DIMENSIONS {} {} {} must be positive", what, d[0], d[1], d[2]));
  if (d[0] * d[1] * d[2] > static_cast<double>(kMaxVoxels))
    throw Error(fmt::format("{}: DATASET_DIMENSIONS {}x{}x{} give more than {} voxels", what, d[0],
                            d[1], d[2], kMaxVoxels));
  const glm::ivec3 dims(static_cast<int>(d[0]), static_cast<int>(d[1]), static_cast<int>(d[2]));
  check_frame_count(dims, frames, what);
  const RawType type = brick_type(a);

  // BYTEORDER_STRING may be absent, meaning the reading machine's order (README.attributes),
  // which is little-endian here.
  bool big_endian = false;
  if (const std::string* order = a.text("BYTEORDER_STRING")) {
    if (*order == "MSB_FIRST")
      big_endian = true;
    else if (*order != "LSB_FIRST")
      throw Error(fmt::format("{}: BYTEORDER_STRING is '{}', neither LSB_FIRST nor MSB_FIRST", what,
                              shown(*order)));
  }

  Layout l;
  // BRICK_FLOAT_FACS: one factor per sub-brick, 0 meaning none (1); all 0: unscaled voxels.
  if (const std::vector<double>* facs = a.numbers("BRICK_FLOAT_FACS", 0)) {
    if (facs->size() > static_cast<size_t>(frames))
      throw Error(fmt::format("{}: BRICK_FLOAT_FACS has {} factors for {} sub-bricks", what,
                              facs->size(), frames));
    bool any = false;
    for (double f : *facs) any = any || f != 0.0;
    if (any) {
      l.scales.assign(static_cast<size_t>(frames), 1.0);
      for (size_t k = 0; k < facs->size(); ++k)
        if ((*facs)[k] != 0.0) l.scales[k] = (*facs)[k];
    }
  }

  l.data.file = files.brik;
  l.data.what = files.data_what;
  require_regular_file(files.brik, files.data_what);
  l.data.gzipped = read_file_head(files.brik, 0, files.data_what).gzipped;
  l.data.offset = 0;
  l.data.type = type;
  l.data.swap = big_endian && raw_type_size(type) > 1;
  l.data.dims = dims;
  l.data.frames = frames;
  l.header.dims = dims;
  l.header.type = l.scales.empty() ? storage_type_for(type) : VoxelType::f32;
  l.header.index_to_world = index_to_lps(a);
  l.header.frames = frames;
  if (labels) l.header.frame_labels = frame_labels(a, frames);
  return l;
}

std::string data_description(const FrameLayout& l) {
  return fmt::format("{}x{}x{} {} x {} sub-brick{}", l.dims.x, l.dims.y, l.dims.z,
                     raw_type_name(l.type), l.frames, l.frames == 1 ? "" : "s");
}

// Inflates the whole BRIK, keeping the box of `frame`; it must inflate to exactly the bytes
// the header describes, and its checksum must hold.
VoxelStorage read_gzip_brik(const FrameLayout& l, int frame, const VoxelBox& box) {
  const glm::ivec3 stacked(l.dims.x, l.dims.y, l.dims.z * l.frames);
  const glm::ivec3 shift(0, 0, l.dims.z * frame);
  const VoxelBox moved{box.lo + shift, box.hi + shift};
  const uint64_t total = l.total_bytes();
  std::error_code ec;
  const uintmax_t size = fs::file_size(l.file, ec);
  if (ec) throw Error(fmt::format("{}: cannot read its size: {}", l.what, ec.message()));
  check_inflatable(static_cast<size_t>(total), static_cast<size_t>(size), l.what);
  refuse_compressed_claim(l.frame_bytes(), VoxelBox::whole(l.dims).count() > kMaxVoxels, l.what,
                          l.frames > 1 ? "gzip voxel data of one frame" : "gzip voxel data");
  std::ifstream in = open_input_stream(l.file, l.what);
  GzipStream stream(in, l.what);
  uint64_t at = 0;
  auto short_data = [&] {
    return Error(fmt::format("{}: inflates to {} bytes, but the header describes {} ({})", l.what,
                             at, total, data_description(l)));
  };
  auto skip_to = [&](uint64_t offset) {
    if (offset <= at) return;
    at += stream.skip(static_cast<size_t>(offset - at));
    if (at < offset) throw short_data();
  };
  VoxelStorage voxels = load_voxels_region(l.type, stacked, moved, l.swap, l.what,
                                           [&](uint64_t offset, std::span<uint8_t> bytes) {
                                             skip_to(offset);
                                             const size_t got = stream.read(bytes);
                                             at += got;
                                             if (got < bytes.size()) throw short_data();
                                           });
  skip_to(total);
  uint8_t extra = 0;
  if (stream.read(std::span<uint8_t>(&extra, 1)) != 0)
    throw Error(fmt::format("{}: inflates to more than the {} bytes the header describes ({})",
                            l.what, total, data_description(l)));
  stream.finish(static_cast<size_t>(total));
  return voxels;
}

// The voxels of `box` of sub-brick `frame`, scaled by its factor.
VoxelStorage read_voxels(const Layout& l, int frame, const VoxelBox& box) {
  VoxelStorage voxels;
  if (l.data.gzipped) {
    voxels = read_gzip_brik(l.data, frame, box);
  } else {
    std::error_code ec;
    const uintmax_t size = fs::file_size(l.data.file, ec);
    if (ec) throw Error(fmt::format("{}: cannot read its size: {}", l.data.what, ec.message()));
    if (size != l.data.total_bytes())
      throw Error(fmt::format("{}: holds {} bytes, but the header describes {} ({}){}", l.data.what,
                              size, l.data.total_bytes(), data_description(l.data),
                              size < l.data.total_bytes() ? " (truncated file?)" : ""));
    voxels = read_frame_voxels(l.data, frame, box);
  }
  if (l.scales.empty()) return voxels;
  const double factor = l.scales[static_cast<size_t>(frame)];
  return std::visit(
      [&](const auto& src) -> VoxelStorage {
        std::vector<float> out(src.size());
        for (size_t i = 0; i < src.size(); ++i)
          out[i] = static_cast<float>(static_cast<double>(src[i]) * factor);
        return VoxelBuffer<float>(std::move(out));
      },
      voxels);
}

}  // namespace

VolumeHeader read_afni_header(const fs::path& file) {
  VolumeHeader header = parse_layout(file, true).header;
  check_placement(header.index_to_world, file.string());
  return header;
}

VolumeData read_afni_region(const fs::path& file, const VoxelBox& box, int frame) {
  const Layout l = parse_layout(file, false);
  return frame_box_volume(l.header, l.data.frames, frame, box, file.string(),
                          [&](const VoxelBox& b) { return read_voxels(l, frame, b); });
}

VolumeData read_afni(const fs::path& file, int frame) {
  const Layout l = parse_layout(file, false);
  return frame_box_volume(l.header, l.data.frames, frame, VoxelBox::whole(l.header.dims),
                          file.string(),
                          [&](const VoxelBox& b) { return read_voxels(l, frame, b); });
}

bool is_afni_head(std::string_view first_bytes) {
  std::string_view s = first_bytes;
  auto skip = [&](std::string_view set) {
    const size_t n = s.find_first_not_of(set);
    s.remove_prefix(n == std::string_view::npos ? s.size() : n);
  };
  skip(" \t\r\n");
  if (!s.starts_with("type")) return false;
  s.remove_prefix(4);
  skip(" \t");
  if (!s.starts_with("=")) return false;
  s.remove_prefix(1);
  skip(" \t");
  for (std::string_view kind : {"string-attribute", "integer-attribute", "float-attribute"})
    if (s.starts_with(kind)) {
      s.remove_prefix(kind.size());
      skip(" \t\r");
      return s.starts_with("\n");
    }
  return false;
}

}  // namespace imx::detail
