#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nifti1_io.h>

#include "intermix/error.hpp"
#include "io/frames.hpp"
#include "io/gzip.hpp"
#include "io/nifti.hpp"
#include "io/raw_voxels.hpp"
#include "io/regular_file.hpp"
#include "volume/volume_checks.hpp"

namespace imx::detail {

namespace {

std::optional<RawType> raw_type(int datatype) {
  switch (datatype) {
    case DT_INT8:
      return RawType::i8;
    case DT_UINT8:
      return RawType::u8;
    case DT_INT16:
      return RawType::i16;
    case DT_UINT16:
      return RawType::u16;
    case DT_INT32:
      return RawType::i32;
    case DT_UINT32:
      return RawType::u32;
    case DT_INT64:
      return RawType::i64;
    case DT_UINT64:
      return RawType::u64;
    case DT_FLOAT32:
      return RawType::f32;
    case DT_FLOAT64:
      return RawType::f64;
    default:
      return std::nullopt;
  }
}

// nifticlib row-major mat44 -> column-major glm, then RAS -> LPS by negating the x and y rows.
glm::dmat4 to_lps(const mat44& m) {
  glm::dmat4 out(1.0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) out[c][r] = (r < 2 ? -1.0 : 1.0) * static_cast<double>(m.m[r][c]);
  return out;
}

int16_t host_order(int16_t v, bool swapped) {
  return swapped ? static_cast<int16_t>(__builtin_bswap16(static_cast<uint16_t>(v))) : v;
}

float host_order(float v, bool swapped) {
  if (!swapped) return v;
  uint32_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  bits = __builtin_bswap32(bits);
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

// Checks the header fields nifticlib would reject, so bad files get one message naming the
// file rather than nifticlib's console output (which it prints whatever its debug level).
void check_header(const std::string& what) {
  znzFile f = znzopen(what.c_str(), "rb", nifti_is_gzfile(what.c_str()));
  if (znz_isnull(f)) throw FileError(fmt::format("{}: cannot open file", what), errno);
  nifti_1_header h{};
  size_t got = znzread(&h, 1, sizeof h, f);
  znzclose(f);
  if (got != sizeof h && nifti_is_gzfile(what.c_str()))
    throw Error(
        fmt::format("{}: corrupt or truncated gzip data: {} of the 348 header bytes "
                    "inflate",
                    what, got > sizeof h ? 0 : got));
  if (got != sizeof h)
    throw Error(fmt::format("{}: too short for a NIfTI-1 header ({} of 348 bytes)", what,
                            got > sizeof h ? 0 : got));
  if (h.sizeof_hdr == 540 || __builtin_bswap32(static_cast<uint32_t>(h.sizeof_hdr)) == 540)
    throw Error(fmt::format("{}: a NIfTI-2 file; only NIfTI-1 is supported", what));
  bool swapped = h.sizeof_hdr != 348;
  if (swapped && __builtin_bswap32(static_cast<uint32_t>(h.sizeof_hdr)) != 348)
    throw Error(
        fmt::format("{}: not a NIfTI-1 file (sizeof_hdr is {}, expected 348)", what, h.sizeof_hdr));
  int ndim = host_order(h.dim[0], swapped);
  if (ndim < 1 || ndim > 7)
    throw Error(
        fmt::format("{}: not a valid NIfTI-1 file (dim[0] is {}, expected 1 to 7)", what, ndim));
  if (ndim < 3) throw Error(fmt::format("{}: has {} dimensions; a volume needs 3", what, ndim));
  for (int d = 1; d <= ndim; ++d)
    if (host_order(h.dim[d], swapped) < 1)
      throw Error(fmt::format("{}: dim[{}] is {}, must be positive", what, d,
                              host_order(h.dim[d], swapped)));
  int datatype = host_order(h.datatype, swapped);
  if (!raw_type(datatype))
    throw Error(
        fmt::format("{}: datatype {} ({}) is not supported (supported: integers of 8 to 64 bits, "
                    "float32, float64)",
                    what, datatype, nifti_datatype_string(datatype)));
  // nifticlib reads a single-file image with a vox_offset inside the header from byte 348, and
  // turns non-finite placement into 0: both are refused here instead.
  const float offset = host_order(h.vox_offset, swapped);
  if (std::memcmp(h.magic, "n+1", 4) == 0 && !(offset >= 352.0f && offset < 2147483648.0f))
    throw Error(fmt::format("{}: vox_offset is {}; a .nii file's data starts at byte 352 or later",
                            what, offset));
  auto finite = [&](const char* field, float value) {
    if (!std::isfinite(host_order(value, swapped)))
      throw Error(fmt::format("{}: {} is {}, not a finite number", what, field,
                              host_order(value, swapped)));
  };
  if (host_order(h.sform_code, swapped) > 0)
    for (int k = 0; k < 4; ++k) {
      finite(fmt::format("srow_x[{}]", k).c_str(), h.srow_x[k]);
      finite(fmt::format("srow_y[{}]", k).c_str(), h.srow_y[k]);
      finite(fmt::format("srow_z[{}]", k).c_str(), h.srow_z[k]);
    }
  if (host_order(h.qform_code, swapped) > 0) {
    finite("quatern_b", h.quatern_b);
    finite("quatern_c", h.quatern_c);
    finite("quatern_d", h.quatern_d);
    finite("qoffset_x", h.qoffset_x);
    finite("qoffset_y", h.qoffset_y);
    finite("qoffset_z", h.qoffset_z);
    for (int k = 0; k < 4; ++k) finite(fmt::format("pixdim[{}]", k).c_str(), h.pixdim[k]);
  }
}

// What the header says about the volume and where its voxels are.
struct Layout {
  VolumeHeader header;
  RawType type = RawType::u8;
  bool swap = false;     // the file's byte order is not the host's
  std::string data;      // the file holding the voxels (the .nii itself, or a .hdr's .img)
  size_t offset = 0;     // where they start in it
  bool gzipped = false;  // it is gzip-compressed
  double slope = 0.0, inter = 0.0;
  // scl_slope/scl_inter change the voxels (slope 0 means "none"), which are then float32.
  bool scaled() const { return slope != 0.0 && !(slope == 1.0 && inter == 0.0); }
};

// Reads and checks the header (nifticlib reads only the header here, not the voxels).
Layout parse_layout(const std::filesystem::path& file) {
  const std::string what = file.string();
  // nifticlib prints its own diagnostics; ours (one message naming the file) replace them.
  static std::once_flag quiet;
  std::call_once(quiet, [] { nifti_set_debug_level(0); });

  check_header(what);
  std::unique_ptr<nifti_image, void (*)(nifti_image*)> nim(nifti_image_read(what.c_str(), 0),
                                                           nifti_image_free);
  if (!nim)
    throw Error(
        fmt::format("{}: not a readable NIfTI-1 file (nifticlib rejected its header)", what));
  if (nim->nx <= 0 || nim->ny <= 0 || nim->nz <= 0)
    throw Error(
        fmt::format("{}: dimensions {}x{}x{} must be positive", what, nim->nx, nim->ny, nim->nz));
  size_t count = static_cast<size_t>(nim->nx) * nim->ny * nim->nz;
  if (count > kMaxVoxels)
    throw Error(fmt::format("{}: dimensions {}x{}x{} give more than {} voxels", what, nim->nx,
                            nim->ny, nim->nz, kMaxVoxels));
  std::optional<RawType> type = raw_type(nim->datatype);
  if (!type) throw Error(fmt::format("{}: datatype {} is not supported", what, nim->datatype));
  if (static_cast<size_t>(nim->nbyper) != raw_type_size(*type))
    throw Error(fmt::format("{}: datatype {} has an unexpected element size {}", what,
                            nifti_datatype_string(nim->datatype), nim->nbyper));

  Layout l;
  l.type = *type;
  l.swap = nim->byteorder != nifti_short_order();
  l.data = nim->iname;
  l.offset = static_cast<size_t>(nim->iname_offset);
  l.gzipped = nifti_is_gzfile(nim->iname);
  l.header.dims = {nim->nx, nim->ny, nim->nz};

  // Intensity scaling, as the NIfTI standard defines it.
  l.slope = nim->scl_slope;
  l.inter = nim->scl_inter;
  if (!std::isfinite(l.slope) || !std::isfinite(l.inter))
    throw Error(
        fmt::format("{}: scl_slope {} / scl_inter {} are not finite", what, l.slope, l.inter));
  l.header.type = l.scaled() ? VoxelType::f32 : storage_type_for(l.type);

  // Placement: sform, else qform, else NIfTI's "method 1" (pixdim scaling only).
  if (nim->sform_code > 0) {
    l.header.index_to_world = to_lps(nim->sto_xyz);
  } else if (nim->qform_code > 0) {
    l.header.index_to_world = to_lps(nim->qto_xyz);
  } else {
    mat44 m{};
    for (int a = 0; a < 3; ++a) {
      float d = nim->pixdim[a + 1];
      m.m[a][a] = std::isfinite(d) && d > 0.0f ? d : 1.0f;  // unset pixdim: unit spacing
    }
    m.m[3][3] = 1.0f;
    l.header.index_to_world = to_lps(m);
  }
  return l;
}

// The voxels of `box`, scaled. The first volume is the first dims voxels after the header (a 4D
// series gives its first time point). Read with znzlib rather than nifti_read_collapsed_image
// (which frees the caller's buffer when a read fails) or nifti_read_subregion_image (which
// neither scales nor converts): uncompressed data is read run by run with seeks past the rest,
// gzip data is inflated to its end, dropping what lies outside the box, so that data short or
// corrupt anywhere is refused as a whole read refuses it.
VoxelStorage read_voxels(const std::filesystem::path& file, const Layout& l, const VoxelBox& box) {
  const std::string what = file.string();
  const glm::ivec3 dims = l.header.dims;
  const size_t needed = static_cast<size_t>(dims.x) * dims.y * dims.z * raw_type_size(l.type);
  std::error_code ec;
  uintmax_t file_size = std::filesystem::file_size(file, ec);
  if (ec) throw Error(fmt::format("{}: cannot read its size: {}", what, ec.message()));
  if (l.gzipped) {
    check_inflatable(needed, static_cast<size_t>(file_size), what);
  } else if (file_size < static_cast<uintmax_t>(l.offset) + needed) {
    uintmax_t found = file_size > l.offset ? file_size - l.offset : 0;
    throw Error(fmt::format("{}: expected {} bytes of voxel data, found {}", what, needed, found));
  }

  require_regular_file(l.data, fmt::format("{} (voxel data of {})", l.data,
                                           what));  // a .hdr's .img may be anything
  znzFile opened = znzopen(l.data.c_str(), "rb", l.gzipped);
  if (znz_isnull(opened))
    throw FileError(fmt::format("{}: cannot open the voxel data", what), errno);
  std::unique_ptr<znzFile, int (*)(znzFile*)> close(&opened, Xznzclose);
  if (znzseek(opened, static_cast<long>(l.offset), SEEK_SET) < 0)
    throw Error(fmt::format("{}: cannot seek to the voxel data at byte {}", what, l.offset));

  size_t at = 0;  // bytes of voxel data read or passed so far
  auto short_data = [&](size_t found) {
    return Error(
        fmt::format("{}: expected {} bytes of voxel data, found {} (file truncated or "
                    "corrupt)",
                    what, needed, found));
  };
  // Reads `size` bytes to `dst`, or drops them when `dst` is null; throws where the data ends.
  std::vector<uint8_t> scratch;
  auto read = [&](uint8_t* dst, size_t size) {
    if (!dst) scratch.resize(std::min(size, size_t{1} << 18));
    size_t done = 0;
    while (done < size) {
      size_t want = std::min(size - done, dst ? size_t{1} << 28 : scratch.size());
      size_t got = znzread(dst ? dst + done : scratch.data(), 1, want, opened);
      if (got == 0 || got > want) break;  // end of data, or a gzip error reported as -1
      done += got;
    }
    at += done;
    if (done != size) throw short_data(at);
  };
  auto advance = [&](size_t offset) {
    if (offset <= at) return;
    if (!l.gzipped) {
      if (znzseek(opened, static_cast<long>(l.offset + offset), SEEK_SET) < 0)
        throw Error(
            fmt::format("{}: cannot seek to the voxel data at byte {}", what, l.offset + offset));
      at = offset;
    } else {
      read(nullptr, offset - at);
    }
  };
  VoxelStorage voxels = load_voxels_region(l.type, dims, box, l.swap, what,
                                           [&](uint64_t offset, std::span<uint8_t> bytes) {
                                             advance(static_cast<size_t>(offset));
                                             read(bytes.data(), bytes.size());
                                           });
  if (l.gzipped) {
    advance(needed);
    // One more byte makes gzip reach its trailer when the data ends here, and check the CRC.
    uint8_t extra;
    if (znzread(&extra, 1, 1, opened) > 1)
      throw Error(fmt::format("{}: corrupt gzip data (its checksum does not match)", what));
  }
  if (!l.scaled()) return voxels;
  return std::visit(
      [&](const auto& src) -> VoxelStorage {
        std::vector<float> out(src.size());
        for (size_t i = 0; i < src.size(); ++i)
          out[i] = static_cast<float>(static_cast<double>(src[i]) * l.slope + l.inter);
        return VoxelBuffer<float>(std::move(out));
      },
      voxels);
}

}  // namespace

VolumeHeader read_nifti_header(const std::filesystem::path& file) {
  VolumeHeader header = parse_layout(file).header;
  check_placement(header.index_to_world, file.string());
  return header;
}

VolumeData read_nifti_region(const std::filesystem::path& file, const VoxelBox& box,
                                int frame) {
  require_frame(frame, 1, file.string());
  const Layout layout = parse_layout(file);
  require_box_inside(layout.header.dims, box, file.string());
  VolumeData v;
  v.dims = box.size();
  v.index_to_world = box_index_to_world(layout.header.index_to_world, box.lo);
  v.voxels = read_voxels(file, layout, box);
  v.validate(file.string());
  return v;
}

VolumeData read_nifti(const std::filesystem::path& file, int frame) {
  require_frame(frame, 1, file.string());
  const Layout layout = parse_layout(file);
  VolumeData v;
  v.dims = layout.header.dims;
  v.index_to_world = layout.header.index_to_world;
  v.voxels = read_voxels(file, layout, VoxelBox::whole(v.dims));
  v.validate(file.string());
  return v;
}

}  // namespace imx::detail
