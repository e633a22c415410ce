// MINC-2 (https://en.wikibooks.org/wiki/MINC/Reference/MINC2.0_File_Format_Reference), read as
// nibabel.minc2 reads it, nibabel being the reference the tests compare to. libhdf5 is behind the
// MINC plugin (minc_hdf5_plugin.hpp, src/minc_hdf5/), which only reads objects and attributes:
// what they mean to MINC (dimensions, placement, scaling, frames) is decided here.
//
// libhdf5 is not hardened against hostile files. This reader is fuzzed (fuzz/fuzz_minc.cpp);
// before HDF5 sees a file its size is bounded and its signature checked, the plugin reaches every
// object through hard links only and refuses data kept outside the file (so a file cannot make
// the reader open another), and every count HDF5 reports is checked before anything is allocated
// for it.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"
#include "io/volume/minc.hpp"
#include "io/volume/minc_hdf5_plugin.hpp"
#include "io/voxels/frame_voxels.hpp"
#include "io/voxels/frames.hpp"
#include "io/voxels/raw_voxels.hpp"
#include "volume/volume_checks.hpp"

namespace imx::detail {

namespace {

namespace fs = std::filesystem;

constexpr std::string_view kHdf5Signature("\x89HDF\r\n\x1a\n", 8);
// The largest uncompressed float64 volume the renderer takes, and room for the header: larger
// files are refused before HDF5 parses them.
constexpr uintmax_t kMaxMincBytes = uintmax_t{kMaxVoxels} * 8 + (uintmax_t{64} << 20);
// Attribute limits: strings and number lists far beyond what MINC writes are corrupt.
constexpr size_t kMaxStringBytes = 4096;
constexpr int64_t kMaxAttributeValues = 64;
// image-min / image-max hold one value per slice, or per slice and frame.
constexpr int64_t kMaxScaleValues = int64_t{1} << 24;

// Where the reader is in the file, for messages: "file: /minc-2.0/image/0/image: ...".
struct Context {
  std::string what;
  [[noreturn]] void fail(const std::string& object, const std::string& message) const {
    throw Error(object.empty() ? fmt::format("{}: {}", what, message)
                               : fmt::format("{}: {}: {}", what, object, message));
  }
};

Hdf5Dataset require_dataset(const Hdf5File& file, const std::string& path, const Context& c) {
  std::optional<Hdf5Dataset> d = file.dataset(path);
  if (!d) c.fail("", fmt::format("has no {} (not a MINC-2 file, or not one nibabel reads)", path));
  if (!d->is_dataset) c.fail(path, "is not a dataset");
  return std::move(*d);
}

std::optional<std::string> string_attribute(const Hdf5File& file, const std::string& path,
                                            const char* name) {
  return file.text(path, name, kMaxStringBytes);
}

std::optional<std::vector<double>> number_attribute(const Hdf5File& file, const std::string& path,
                                                    const char* name) {
  return file.numbers(path, name, kMaxAttributeValues);
}

std::optional<double> one_number(const Hdf5File& file, const std::string& path, const char* name,
                                 const Context& c) {
  const std::optional<std::vector<double>> v = number_attribute(file, path, name);
  if (!v) return std::nullopt;
  if (v->size() != 1)
    c.fail(path, fmt::format("attribute '{}' holds {} values, not 1", name, v->size()));
  return v->front();
}

// An attribute 'dimorder' ("zspace,yspace,xspace") cut to `rank` names, as nibabel cuts it.
std::vector<std::string> dimension_names(const Hdf5File& file, const std::string& path,
                                         size_t rank) {
  const std::optional<std::string> order = string_attribute(file, path, "dimorder");
  std::vector<std::string> names;
  if (!order) return names;
  size_t start = 0;
  while (names.size() < rank) {
    const size_t comma = order->find(',', start);
    names.push_back(order->substr(start, comma == std::string::npos ? comma : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return names;
}

// The file's element type.
struct ElementType {
  RawType raw = RawType::u8;
  bool is_float = false;
  double min = 0, max = 0;  // an integer type's range
};

ElementType element_type(const Hdf5Dataset& d, const Context& c, const std::string& path) {
  const size_t size = static_cast<size_t>(d.element_size);
  ElementType t;
  if (d.element == Hdf5Dataset::Element::floating && (size == 4 || size == 8)) {
    t.is_float = true;
    t.raw = size == 4 ? RawType::f32 : RawType::f64;
    return t;
  }
  if (d.element != Hdf5Dataset::Element::integer)
    c.fail(path, "voxels are neither integers nor floating point: not supported");
  const bool is_signed = d.element_signed;
  switch (size) {
    case 1:
      t.raw = is_signed ? RawType::i8 : RawType::u8;
      t.min = is_signed ? -128.0 : 0.0;
      t.max = is_signed ? 127.0 : 255.0;
      break;
    case 2:
      t.raw = is_signed ? RawType::i16 : RawType::u16;
      t.min = is_signed ? -32768.0 : 0.0;
      t.max = is_signed ? 32767.0 : 65535.0;
      break;
    case 4:
      t.raw = is_signed ? RawType::i32 : RawType::u32;
      t.min = is_signed ? -2147483648.0 : 0.0;
      t.max = is_signed ? 2147483647.0 : 4294967295.0;
      break;
    case 8:
      t.raw = is_signed ? RawType::i64 : RawType::u64;
      t.min = is_signed ? -9223372036854775808.0 : 0.0;
      t.max = is_signed ? 9223372036854775807.0 : 18446744073709551615.0;
      break;
    default:
      c.fail(path, fmt::format("voxels are {}-byte integers: not supported", size));
  }
  return t;
}

constexpr const char* kImagePath = "/minc-2.0/image/0/image";
constexpr const char* kImageMaxPath = "/minc-2.0/image/0/image-max";
constexpr const char* kImageMinPath = "/minc-2.0/image/0/image-min";

struct Layout {
  VolumeHeader header;
  std::vector<int64_t> shape;    // the image's dims, file order (slowest first)
  std::array<int, 3> spatial{};  // which file dims are i, j, k
  int time = -1;                 // which file dim is time, or -1
  ElementType type;
  bool identity = true;  // integer data whose scaling changes nothing, or float data
  // Integer scaling: clip to [vmin, vmax], then value * slope[s] + inter[s], s indexing the
  // first `scale_dims` file dims (row-major), as nibabel's Minc1File._normalize does.
  double vmin = 0, vmax = 0;
  int scale_dims = 0;
  std::vector<double> slope, inter;
};

// The whole of image-min or image-max, whose `shape` the caller has checked.
std::vector<double> read_scale(const Hdf5File& file, const char* path,
                               const std::vector<int64_t>& shape) {
  int64_t count = 1;
  for (int64_t n : shape) count *= n;
  std::vector<double> values(static_cast<size_t>(count));
  const std::vector<int64_t> start(shape.size(), 0);
  file.read(path, RawType::f64, start, shape,
            {reinterpret_cast<uint8_t*>(values.data()), values.size() * sizeof(double)});
  return values;
}

// nibabel's Minc1File._normalize set-up: valid_range (or the type's range), image-min and
// image-max over the image's first dims (none: one pair for the whole image).
void read_scaling(const Hdf5File& file, const std::vector<std::string>& names, Layout& l,
                  const Context& c) {
  const Hdf5Dataset max = require_dataset(file, kImageMaxPath, c);
  const Hdf5Dataset min = require_dataset(file, kImageMinPath, c);
  if (l.type.is_float) return;  // nibabel reads floating point voxels as they are
  const std::vector<int64_t>& max_shape = max.dims;
  const std::vector<int64_t>& min_shape = min.dims;
  const std::vector<std::string> max_names = dimension_names(file, kImageMaxPath, max_shape.size());
  const std::vector<std::string> min_names = dimension_names(file, kImageMinPath, min_shape.size());
  if (max_names != min_names) c.fail("", "image-max and image-min do not have the same dimensions");
  const size_t n = max_names.size();
  if (n > 2) c.fail(kImageMaxPath, "varies along more than two dimensions: not supported");
  if (!std::equal(max_names.begin(), max_names.end(), names.begin()))
    c.fail(kImageMaxPath, "its dimensions are not the image's first dimensions");
  std::vector<int64_t> want(l.shape.begin(), l.shape.begin() + static_cast<std::ptrdiff_t>(n));
  int64_t count = 1;
  for (int64_t v : want) count *= v;
  if (count > kMaxScaleValues) c.fail(kImageMaxPath, fmt::format("holds {} values", count));
  for (const auto& [shape, path] :
       {std::pair{max_shape, kImageMaxPath}, std::pair{min_shape, kImageMinPath}}) {
    // Without dims a single value scales the whole image; with them, one per index.
    int64_t points = 1;
    for (int64_t v : shape) points *= v;
    if (n == 0 ? points != 1 : shape != want)
      c.fail(path, fmt::format("holds {} values where the image needs {}", points, count));
  }
  const std::vector<double> imax = read_scale(file, kImageMaxPath, n == 0 ? max_shape : want);
  const std::vector<double> imin = read_scale(file, kImageMinPath, n == 0 ? min_shape : want);

  l.vmin = l.type.min;
  l.vmax = l.type.max;
  if (const auto range = number_attribute(file, kImagePath, "valid_range")) {
    if (range->size() < 2) c.fail(kImagePath, "attribute 'valid_range' holds fewer than 2 values");
    if ((*range)[0] < l.type.min || (*range)[1] > l.type.max)
      c.fail(kImagePath, fmt::format("valid_range {} .. {} lies outside the {} type's range",
                                     (*range)[0], (*range)[1], raw_type_name(l.type.raw)));
    l.vmin = (*range)[0];
    l.vmax = (*range)[1];
  }
  if (!(l.vmax > l.vmin))
    c.fail(kImagePath, fmt::format("valid_range {} .. {} is empty", l.vmin, l.vmax));
  l.scale_dims = static_cast<int>(n);
  l.slope.resize(imax.size());
  l.inter.resize(imax.size());
  for (size_t s = 0; s < imax.size(); ++s) {
    l.slope[s] = (imax[s] - imin[s]) / (l.vmax - l.vmin);
    l.inter[s] = imin[s] - l.vmin * l.slope[s];
  }
  const bool keeps_type =
      l.type.raw == RawType::u8 || l.type.raw == RawType::i16 || l.type.raw == RawType::u16;
  l.identity = keeps_type && l.vmin == l.type.min && l.vmax == l.type.max &&
               std::all_of(l.slope.begin(), l.slope.end(), [](double v) { return v == 1.0; }) &&
               std::all_of(l.inter.begin(), l.inter.end(), [](double v) { return v == 0.0; });
}

Layout parse_file(const Hdf5File& file, const Context& c) {
  const Hdf5Dataset image = require_dataset(file, kImagePath, c);
  Layout l;
  l.shape = image.dims;
  for (int64_t n : l.shape)
    if (n < 1) c.fail(kImagePath, "has an empty dimension");
  const std::vector<std::string> names = dimension_names(file, kImagePath, l.shape.size());
  if (names.size() != l.shape.size())
    c.fail(kImagePath, fmt::format("its 'dimorder' names {} dimensions for {} (nibabel needs 3 "
                                   "spatial dimensions)",
                                   names.size(), l.shape.size()));
  l.type = element_type(image, c, kImagePath);

  // nibabel's get_affine: the spatial dims (names ending in "space") in file order give the
  // columns: direction cosines (default: the axis the name says) times step, origin cosines
  // times start.
  glm::dmat4 ras(1.0);
  glm::dvec3 starts(0.0);
  glm::dmat3 cosines(1.0);
  int spatial = 0;
  double time_step = 0.0;
  for (size_t d = 0; d < names.size(); ++d) {
    const std::string& name = names[d];
    if (name.empty() || name.find('/') != std::string::npos || name.size() > 64)
      c.fail(kImagePath,
             fmt::format("dimension name '{}' in 'dimorder' is not valid", shown(name)));
    const std::string path = "/minc-2.0/dimensions/" + name;
    if (!file.dataset(path))
      c.fail("", fmt::format("has no {} for the image's dimension '{}'", path, name));
    const std::optional<std::string> spacing = string_attribute(file, path, "spacing");
    if (spacing != "regular__")
      c.fail(path, fmt::format("spacing is '{}', not 'regular__': irregular spacing is not "
                               "supported",
                               spacing ? shown(*spacing) : "(none)"));
    const bool is_spatial = name.size() >= 5 && name.compare(name.size() - 5, 5, "space") == 0;
    if (!is_spatial) {
      if (name != "time" || l.time >= 0)
        c.fail(kImagePath, fmt::format("dimension '{}' is not supported (3 spatial dimensions and "
                                       "an optional 'time')",
                                       shown(name)));
      l.time = static_cast<int>(d);
      time_step = one_number(file, path, "step", c).value_or(0.0);
      if (const auto units = string_attribute(file, path, "units");
          units && (*units == "ms" || *units == "msec"))
        time_step /= 1000.0;
      continue;
    }
    if (spatial == 3) c.fail(kImagePath, "has more than 3 spatial dimensions");
    l.spatial[static_cast<size_t>(spatial)] = static_cast<int>(d);
    glm::dvec3 axis(0.0);
    if (const auto cos = number_attribute(file, path, "direction_cosines")) {
      if (cos->size() != 3)
        c.fail(path, fmt::format("direction_cosines holds {} values, not 3", cos->size()));
      axis = glm::dvec3((*cos)[0], (*cos)[1], (*cos)[2]);
    } else if (name == "xspace" || name == "yspace" || name == "zspace") {
      axis[name[0] - 'x'] = 1.0;
    } else {
      c.fail(path, "has no direction_cosines, and its name gives no default axis");
    }
    cosines[spatial] = axis;
    const double step = one_number(file, path, "step", c).value_or(1.0);
    starts[spatial] = one_number(file, path, "start", c).value_or(0.0);
    ras[spatial] = glm::dvec4(axis * step, 0.0);
    ++spatial;
  }
  if (spatial != 3)
    c.fail(kImagePath, fmt::format("has {} spatial dimensions: the image needs 3", spatial));
  ras[3] = glm::dvec4(cosines * starts, 1.0);
  for (int col = 0; col < 4; ++col) {
    ras[col][0] = -ras[col][0];
    ras[col][1] = -ras[col][1];
  }

  const glm::ivec3 dims(static_cast<int>(l.shape[static_cast<size_t>(l.spatial[0])]),
                        static_cast<int>(l.shape[static_cast<size_t>(l.spatial[1])]),
                        static_cast<int>(l.shape[static_cast<size_t>(l.spatial[2])]));
  if (static_cast<double>(dims.x) * dims.y * dims.z > static_cast<double>(kMaxVoxels))
    c.fail(kImagePath,
           fmt::format("{}x{}x{} is more than {} voxels", dims.x, dims.y, dims.z, kMaxVoxels));
  const int64_t frames = l.time >= 0 ? l.shape[static_cast<size_t>(l.time)] : 1;
  check_frame_count(dims, frames, c.what);
  read_scaling(file, names, l, c);

  l.header.dims = dims;
  l.header.index_to_world = ras;
  l.header.frames = static_cast<int>(frames);
  l.header.type = l.identity && !l.type.is_float ? storage_type_for(l.type.raw) : VoxelType::f32;
  if (frames > 1 && std::isfinite(time_step) && time_step != 0.0) {
    l.header.frame_labels.resize(static_cast<size_t>(frames));
    for (int64_t k = 0; k < frames; ++k) {
      FrameLabel& label = l.header.frame_labels[static_cast<size_t>(k)];
      label.time_s = static_cast<double>(k) * time_step;
      label.text = describe_frame(label);
    }
  }
  return l;
}

// The box's voxels of frame `frame`, read as one hyperslab in the file's type, then scaled and
// moved to i-fastest order (i being the file's slowest spatial dim).
template <class Source, class Target>
void convert(const Layout& l, const std::vector<uint8_t>& buffer, int frame, const VoxelBox& box,
             Target* out) {
  const glm::ivec3 size = box.size();
  const Source* in = reinterpret_cast<const Source*>(buffer.data());
  // The scale index from the first scale_dims file dims, which never include k (the fastest
  // spatial dim), so it is set per (i, j) row.
  auto scale_index = [&](int i, int j) {
    size_t s = 0;
    for (int d = 0; d < l.scale_dims; ++d) {
      int64_t coordinate = frame;
      if (d == l.spatial[0]) coordinate = box.lo.x + i;
      if (d == l.spatial[1]) coordinate = box.lo.y + j;
      s = s * static_cast<size_t>(l.shape[static_cast<size_t>(d)]) +
          static_cast<size_t>(coordinate);
    }
    return s;
  };
  const size_t plane = static_cast<size_t>(size.x) * size.y;
  for (int i = 0; i < size.x; ++i)
    for (int j = 0; j < size.y; ++j) {
      const Source* row = in + (static_cast<size_t>(i) * size.y + j) * size.z;
      Target* target = out + static_cast<size_t>(j) * size.x + i;
      if constexpr (std::is_same_v<Source, Target>) {
        for (int k = 0; k < size.z; ++k) target[k * plane] = row[k];
      } else if (l.type.is_float || l.identity) {
        for (int k = 0; k < size.z; ++k) target[k * plane] = static_cast<Target>(row[k]);
      } else {
        const size_t s = scale_index(i, j);
        const double slope = l.slope[s], inter = l.inter[s];
        for (int k = 0; k < size.z; ++k) {
          const double v = std::clamp(static_cast<double>(row[k]), l.vmin, l.vmax);
          target[k * plane] = static_cast<Target>(v * slope + inter);
        }
      }
    }
}

template <class Target>
void convert_from(const Layout& l, const std::vector<uint8_t>& buffer, int frame,
                  const VoxelBox& box, Target* out) {
  switch (l.type.raw) {
    case RawType::i8:
      return convert<int8_t>(l, buffer, frame, box, out);
    case RawType::u8:
      return convert<uint8_t>(l, buffer, frame, box, out);
    case RawType::i16:
      return convert<int16_t>(l, buffer, frame, box, out);
    case RawType::u16:
      return convert<uint16_t>(l, buffer, frame, box, out);
    case RawType::i32:
      return convert<int32_t>(l, buffer, frame, box, out);
    case RawType::u32:
      return convert<uint32_t>(l, buffer, frame, box, out);
    case RawType::i64:
      return convert<int64_t>(l, buffer, frame, box, out);
    case RawType::u64:
      return convert<uint64_t>(l, buffer, frame, box, out);
    case RawType::f32:
      return convert<float>(l, buffer, frame, box, out);
    case RawType::f64:
      return convert<double>(l, buffer, frame, box, out);
  }
}

VoxelStorage read_box(const Hdf5File& file, const Layout& l, int frame, const VoxelBox& box,
                      const Context& c) {
  const size_t rank = l.shape.size();
  std::vector<int64_t> start(rank, 0), count(rank, 1);
  for (int a = 0; a < 3; ++a) {
    start[static_cast<size_t>(l.spatial[a])] = box.lo[a];
    count[static_cast<size_t>(l.spatial[a])] = box.size()[a];
  }
  if (l.time >= 0) start[static_cast<size_t>(l.time)] = frame;
  const uint64_t raw_bytes = box.count() * raw_type_size(l.type.raw);
  check_memory(raw_bytes + box.count() * sizeof(float), c.what);
  std::vector<uint8_t> buffer(static_cast<size_t>(raw_bytes));
  file.read(kImagePath, l.type.raw, start, count, buffer);
  const RawType target = l.header.type == VoxelType::f32 ? RawType::f32 : l.type.raw;
  return load_voxels(target, box.count(), false, c.what, [&](std::span<uint8_t> out) {
    switch (l.header.type) {
      case VoxelType::u8:
        return convert_from(l, buffer, frame, box, reinterpret_cast<uint8_t*>(out.data()));
      case VoxelType::i16:
        return convert_from(l, buffer, frame, box, reinterpret_cast<int16_t*>(out.data()));
      case VoxelType::u16:
        return convert_from(l, buffer, frame, box, reinterpret_cast<uint16_t*>(out.data()));
      case VoxelType::f32:
        return convert_from(l, buffer, frame, box, reinterpret_cast<float*>(out.data()));
    }
  });
}

// Opens `file` with HDF5 (through the plugin) after the checks that keep hostile input from it,
// and hands the open file to `use`. A MINC-1 file or one that is not HDF5 never loads the plugin.
template <class F>
auto with_minc_file(const fs::path& file, F&& use) {
  const Context c{file.string()};
  const InputFd fd = open_input(file, c.what);  // HDF5 then opens this descriptor's file
  const uint64_t size = fd.size();
  if (size > kMaxMincBytes)
    c.fail("", fmt::format("{} bytes is more than a MINC file intermix reads ({} at most)", size,
                           kMaxMincBytes));
  std::string head(8, '\0');
  {
    std::ifstream in(path_of_open(fd, file), std::ios::binary);
    in.read(head.data(), 8);
    head.resize(static_cast<size_t>(in.gcount()));
  }
  if (head.rfind("CDF\x01", 0) == 0 || head.rfind("CDF\x02", 0) == 0)
    c.fail("",
           "is a MINC-1 (netCDF) file, which intermix does not read: convert it to MINC-2 "
           "with 'mincconvert -2 in.mnc out.mnc', or load it with nibabel and save it as "
           "NIfTI");
  if (head != kHdf5Signature) c.fail("", "does not start with HDF5's signature: not a MINC-2 file");
  const Hdf5File h(file, path_of_open(fd, file));
  return use(h, c);
}

}  // namespace

bool is_minc(std::string_view first_bytes) {
  return first_bytes.rfind(kHdf5Signature, 0) == 0 ||
         first_bytes.rfind(std::string_view("CDF\x01", 4), 0) == 0 ||
         first_bytes.rfind(std::string_view("CDF\x02", 4), 0) == 0;
}

VolumeHeader read_minc_header_in_process(const std::filesystem::path& file) {
  VolumeHeader header = with_minc_file(
      file, [](const Hdf5File& h, const Context& c) { return parse_file(h, c).header; });
  check_placement(header.index_to_world, file.string());
  return header;
}

VoxelStorage read_minc_box_in_process(const std::filesystem::path& file, int frame,
                                      const VoxelBox& box) {
  return with_minc_file(file, [&](const Hdf5File& h, const Context& c) {
    const Layout l = parse_file(h, c);
    require_frame(frame, l.header.frames, c.what);
    require_box_inside(l.header.dims, box, c.what);
    return read_box(h, l, frame, box, c);
  });
}

}  // namespace imx::detail
