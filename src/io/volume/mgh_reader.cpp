// FreeSurfer's MGH format (https://surfer.nmr.mgh.harvard.edu/fswiki/FsTutorial/MghFormat), read
// as nibabel's freesurfer.mghformat reads it, nibabel being the reference the tests compare to.
#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/file_head.hpp"
#include "io/streams/gzip.hpp"
#include "io/streams/input_file.hpp"
#include "io/volume/mgh.hpp"
#include "io/voxels/frame_voxels.hpp"
#include "io/voxels/frames.hpp"
#include "io/voxels/raw_voxels.hpp"
#include "volume/volume_checks.hpp"

namespace imx::detail {

namespace {

// The header's fixed fields (version .. Pxyz_c) fill its first 90 bytes; the voxels start at
// byte 284, and after them come the optional footer's TR, flip angle, TE, TI and FOV, and tags.
constexpr size_t kHeaderBytes = 90;
constexpr uint64_t kDataOffset = 284;

// A big-endian field at `offset` of the header.
template <class T>
T big_endian(const std::string& bytes, size_t offset) {
  char raw[sizeof(T)];
  std::memcpy(raw, bytes.data() + offset, sizeof(T));
  std::reverse(raw, raw + sizeof(T));  // the host is little-endian (raw_voxels.cpp asserts it)
  T value;
  std::memcpy(&value, raw, sizeof(T));
  return value;
}

std::optional<RawType> raw_type(int32_t type) {
  switch (type) {
    case 0:  // MRI_UCHAR
      return RawType::u8;
    case 1:  // MRI_INT
      return RawType::i32;
    case 3:  // MRI_FLOAT
      return RawType::f32;
    case 4:  // MRI_SHORT
      return RawType::i16;
    default:
      return std::nullopt;
  }
}

struct Layout {
  VolumeHeader header;
  FrameLayout data;
};

// vox2ras as nibabel's MGHHeader.get_affine computes it: the columns are the direction cosines
// Mdc (stored as x_r x_a x_s, y_r ..., one axis after the other) times the voxel sizes, and the
// centre of the grid, at index dims / 2 (not an integer division, and not (dims - 1) / 2), lies
// at c_ras: P0 = c_ras - M * dims / 2. Then RAS -> LPS: the x and y rows negated.
glm::dmat4 vox2ras_lps(const std::array<double, 3>& size, const std::array<double, 9>& mdc,
                       const std::array<double, 3>& c_ras, glm::ivec3 dims) {
  glm::dmat4 m(1.0);
  for (int axis = 0; axis < 3; ++axis)
    for (int r = 0; r < 3; ++r) m[axis][r] = mdc[3 * axis + r] * size[axis];
  const glm::dvec3 centre = glm::dmat3(m) * (glm::dvec3(dims) / 2.0);
  for (int r = 0; r < 3; ++r) m[3][r] = c_ras[r] - centre[r];
  for (int c = 0; c < 4; ++c) {
    m[c][0] = -m[c][0];
    m[c][1] = -m[c][1];
  }
  return m;
}

// The footer's TR in ms (0 when the file has no footer), found after every frame's data.
float footer_tr(const std::filesystem::path& file, bool gzipped, uint64_t data_end,
                const std::string& what) {
  std::ifstream in = open_input_stream(file, what);
  std::string tr(4, '\0');
  auto* out = reinterpret_cast<uint8_t*>(tr.data());
  size_t got = 0;
  if (gzipped) {
    GzipStream stream(in, what);
    if (stream.skip(static_cast<size_t>(data_end)) == data_end)
      got = stream.read(std::span<uint8_t>(out, 4));
  } else {
    in.seekg(static_cast<std::streamoff>(data_end));
    in.read(tr.data(), 4);
    got = in ? 4 : 0;
  }
  return got == 4 ? big_endian<float>(tr, 0) : 0.0f;
}

// Reads and checks the header; `labels`: also the footer's TR, for the frames' times.
Layout parse_layout(const std::filesystem::path& file, bool labels) {
  const std::string what = file.string();
  const FileHead head = read_file_head(file, kHeaderBytes, what);
  const std::string& b = head.bytes;
  if (b.size() < kHeaderBytes)
    throw Error(head.gzipped ? fmt::format("{}: corrupt or truncated gzip data: {} of the {} MGH "
                                           "header bytes inflate",
                                           what, b.size(), kHeaderBytes)
                             : fmt::format("{}: too short for an MGH header ({} of {} bytes)", what,
                                           b.size(), kHeaderBytes));
  const int32_t version = big_endian<int32_t>(b, 0);
  if (version != 1)
    throw Error(fmt::format("{}: version is {}, not 1: not an MGH file", what, version));
  const int32_t width = big_endian<int32_t>(b, 4), height = big_endian<int32_t>(b, 8),
                depth = big_endian<int32_t>(b, 12), nframes = big_endian<int32_t>(b, 16);
  const int32_t type_code = big_endian<int32_t>(b, 20);
  if (width < 1 || height < 1 || depth < 1 || nframes < 1)
    throw Error(fmt::format("{}: dimensions {}x{}x{} with {} frames must all be positive", what,
                            width, height, depth, nframes));
  const glm::ivec3 dims(width, height, depth);
  // In double: three int32 sizes can overflow a uint64 product back into range.
  if (static_cast<double>(width) * height * depth > static_cast<double>(kMaxVoxels))
    throw Error(fmt::format("{}: dimensions {}x{}x{} give more than {} voxels", what, width, height,
                            depth, kMaxVoxels));
  const std::optional<RawType> type = raw_type(type_code);
  if (!type)
    throw Error(
        fmt::format("{}: type {} is not supported (MGH types: 0 uchar, 1 int, 3 float, "
                    "4 short)",
                    what, type_code));
  check_frame_count(dims, nframes, what);

  // With goodRASflag 0 the direction fields are not valid: nibabel (MGHHeader.
  // _set_affine_default) then uses unit voxels, these directions and c_ras 0, whatever the
  // fields hold.
  std::array<double, 3> size{1.0, 1.0, 1.0}, c_ras{0.0, 0.0, 0.0};
  std::array<double, 9> mdc{-1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0};
  if (big_endian<int16_t>(b, 28) != 0) {
    auto field = [&](const char* name, size_t offset) {
      const double v = big_endian<float>(b, offset);
      if (!std::isfinite(v))
        throw Error(fmt::format("{}: {} is {}, not a finite number", what, name, v));
      return v;
    };
    static const char* const size_names[3] = {"xsize", "ysize", "zsize"};
    static const char* const mdc_names[9] = {"x_r", "x_a", "x_s", "y_r", "y_a",
                                             "y_s", "z_r", "z_a", "z_s"};
    static const char* const c_names[3] = {"c_r", "c_a", "c_s"};
    for (int k = 0; k < 3; ++k) size[k] = field(size_names[k], 30 + 4 * k);
    for (int k = 0; k < 9; ++k) mdc[k] = field(mdc_names[k], 42 + 4 * k);
    for (int k = 0; k < 3; ++k) c_ras[k] = field(c_names[k], 78 + 4 * k);
  }

  Layout l;
  l.data.file = file;
  l.data.what = what;
  l.data.gzipped = head.gzipped;
  l.data.offset = kDataOffset;
  l.data.type = *type;
  l.data.swap = true;  // big-endian
  l.data.dims = dims;
  l.data.frames = nframes;
  l.header.dims = dims;
  l.header.type = storage_type_for(*type);
  l.header.index_to_world = vox2ras_lps(size, mdc, c_ras, dims);
  l.header.frames = nframes;
  if (labels && nframes > 1) {
    // The footer's TR (ms) is the time from one frame to the next in FreeSurfer's functional
    // series (nibabel gives it as the fourth zoom).
    const double tr = footer_tr(file, head.gzipped, kDataOffset + l.data.total_bytes(), what);
    if (std::isfinite(tr) && tr > 0.0) {
      l.header.frame_labels.resize(static_cast<size_t>(nframes));
      for (int k = 0; k < nframes; ++k) {
        l.header.frame_labels[k].time_s = k * tr / 1000.0;
        l.header.frame_labels[k].text = describe_frame(l.header.frame_labels[k]);
      }
    }
  }
  return l;
}

}  // namespace

VolumeHeader read_mgh_header(const std::filesystem::path& file) {
  VolumeHeader header = parse_layout(file, true).header;
  check_placement(header.index_to_world, file.string());
  return header;
}

VolumeData read_mgh_region(const std::filesystem::path& file, const VoxelBox& box, int frame) {
  const Layout l = parse_layout(file, false);
  return frame_box_volume(l.header, l.data.frames, frame, box, file.string(),
                          [&](const VoxelBox& b) { return read_frame_voxels(l.data, frame, b); });
}

VolumeData read_mgh(const std::filesystem::path& file, int frame) {
  const Layout l = parse_layout(file, false);
  return frame_box_volume(l.header, l.data.frames, frame, VoxelBox::whole(l.header.dims),
                          file.string(),
                          [&](const VoxelBox& b) { return read_frame_voxels(l.data, frame, b); });
}

}  // namespace imx::detail
