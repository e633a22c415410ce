#include "io/voxels/nifti_header.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <optional>

#include <fmt/format.h>
#include <nifti1_io.h>
#include <nifti2.h>

#include "intermix/error.hpp"

namespace imx::detail {

namespace {

static_assert(sizeof(nifti_1_header) == 348 && sizeof(nifti_2_header) == 540,
              "nifticlib's header structs give the on-disk field offsets");

// Analyze 7.5's data_history puts `char orient` at byte 252 and `char originator[10]` right
// after it, which SPM reads as three int16 voxel indices at byte 253 (not 2-byte aligned, so no
// field of nifti_1_header lies there: NIfTI-1 put qform_code and sform_code on those bytes).
constexpr size_t kAnalyzeOrigin = 253;

// Fields read at byte offsets of a header in either byte order.
class Fields {
 public:
  Fields(std::string_view bytes, bool swapped) : bytes_(bytes), swapped_(swapped) {}

  template <class T>
  T get(size_t offset) const {
    char raw[sizeof(T)];
    std::memcpy(raw, bytes_.data() + offset, sizeof(T));
    if (swapped_) std::reverse(raw, raw + sizeof(T));
    T value;
    std::memcpy(&value, raw, sizeof(T));
    return value;
  }

 private:
  std::string_view bytes_;
  bool swapped_;
};

#define IMX_N1(field) offsetof(nifti_1_header, field)
#define IMX_N2(field) offsetof(nifti_2_header, field)

// A magic for a message: its printable characters, others as \xNN, trailing NULs dropped
// (unless it is nothing but NULs).
std::string shown_magic(std::string_view magic) {
  while (magic.size() > 1 && magic.back() == '\0' && magic.find_first_not_of('\0') < magic.size())
    magic.remove_suffix(1);
  std::string out;
  for (char c : magic) {
    const auto u = static_cast<unsigned char>(c);
    out += u >= 0x20 && u < 0x7f ? std::string(1, c) : fmt::format("\\x{:02x}", u);
  }
  return out;
}

// nifticlib's test for a NIfTI magic of any version: "n", "i" or "+", a digit, a NUL.
bool nifti_like_magic(std::string_view m) {
  return m.size() >= 4 && m[0] == 'n' && (m[1] == 'i' || m[1] == '+') && m[2] >= '1' &&
         m[2] <= '9' && m[3] == '\0';
}

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

// The magic a header of this kind and file layout must carry, and what it is called.
void check_magic(std::string_view magic, int sizeof_hdr, bool pair, NiftiHeader& h,
                 const std::string& what) {
  const std::string m = shown_magic(magic.substr(0, 4));
  if (sizeof_hdr == 540) {
    const char* want = pair ? "ni2" : "n+2";
    if (std::memcmp(magic.data(), want, 4) != 0) {
      const bool other_layout = std::memcmp(magic.data(), pair ? "n+2" : "ni2", 4) == 0;
      throw Error(
          other_layout
              ? fmt::format("{}: magic is '{}', that of {}; {} says '{}'", what, m,
                            pair ? "a single .nii file" : "a .hdr/.img pair",
                            pair ? "the .hdr of a pair" : "a single .nii file", want)
              : fmt::format("{}: magic is '{}' where a NIfTI-2 {} has '{}': not a NIfTI-2 file",
                            what, m, pair ? ".hdr" : ".nii", want));
    }
    // Bytes 8-11 catch a transfer that rewrote line ends; nibabel also accepts them zeroed.
    const std::string_view eol = magic.substr(4, 4);
    if (eol != std::string_view("\r\n\032\n", 4) && eol != std::string_view("\0\0\0\0", 4))
      throw Error(
          fmt::format("{}: bytes 8-11 are '{}', not NIfTI-2's \\r\\n\\x1a\\n check: the file was "
                      "altered (a text-mode transfer?)",
                      what, shown_magic(eol)));
    h.kind = NiftiKind::nifti2;
    h.single_file = !pair;
    return;
  }
  h.single_file = !pair;
  if (!pair) {
    if (std::memcmp(magic.data(), "n+1", 4) == 0) {
      h.kind = NiftiKind::nifti1;
      return;
    }
    if (std::memcmp(magic.data(), "ni1", 4) == 0)
      throw Error(fmt::format(
          "{}: magic is 'ni1', that of a .hdr/.img pair; a single .nii file says 'n+1'", what));
    // nifticlib would read this as Analyze 7.5, without the sform and qform: refused instead.
    throw Error(
        fmt::format("{}: magic is '{}' where a NIfTI-1 .nii file has 'n+1' (bytes 344-347): not a "
                    "NIfTI-1 file, and not read as Analyze 7.5 (that would drop its orientation)",
                    what, m));
  }
  if (std::memcmp(magic.data(), "ni1", 4) == 0) {
    h.kind = NiftiKind::nifti1;
    return;
  }
  if (std::memcmp(magic.data(), "n+1", 4) == 0)
    throw Error(
        fmt::format("{}: magic is 'n+1', that of a single .nii file; the .hdr of a pair says "
                    "'ni1'",
                    what));
  if (nifti_like_magic(magic))
    throw Error(fmt::format(
        "{}: magic is '{}' in a 348-byte header: neither NIfTI-1 ('ni1') nor Analyze 7.5", what,
        m));
  h.kind = NiftiKind::analyze;  // no magic: Analyze keeps other data on these bytes
}

void check_dims(NiftiHeader& h, const std::string& what) {
  if (h.ndim < 1 || h.ndim > 7)
    throw Error(fmt::format("{}: not a valid {} header (dim[0] is {}, expected 1 to 7)", what,
                            nifti_kind_name(h.kind), h.ndim));
  if (h.ndim < 3) throw Error(fmt::format("{}: has {} dimensions; a volume needs 3", what, h.ndim));
  for (int d = 1; d <= h.ndim; ++d)
    if (h.dim[d] < 1)
      throw Error(fmt::format("{}: dim[{}] is {}, must be positive", what, d, h.dim[d]));
  for (int d = h.ndim + 1; d < 8; ++d) h.dim[d] = 1;  // beyond dim[0]: unused
}

void check_datatype(NiftiHeader& h, const std::string& what) {
  std::optional<RawType> type = raw_type(h.datatype);
  // nibabel's Analyze 7.5 types: the others are NIfTI's additions.
  const bool analyze_type = h.datatype == DT_UINT8 || h.datatype == DT_INT16 ||
                            h.datatype == DT_INT32 || h.datatype == DT_FLOAT32 ||
                            h.datatype == DT_FLOAT64;
  if (h.kind == NiftiKind::analyze && !analyze_type)
    throw Error(fmt::format(
        "{}: datatype {} ({}) is not supported in an Analyze 7.5 header (supported: uint8, "
        "int16, int32, float32, float64)",
        what, h.datatype, nifti_datatype_string(h.datatype)));
  if (h.datatype == DT_RGB24 || h.datatype == DT_RGBA32) {  // a colour volume
    h.type = RawType::u8;
    h.colour_channels = h.datatype == DT_RGB24 ? 3 : 4;
    return;
  }
  if (!type)
    throw Error(
        fmt::format("{}: datatype {} ({}) is not supported (supported: integers of 8 to 64 bits, "
                    "float32, float64, RGB24, RGBA32)",
                    what, h.datatype, nifti_datatype_string(h.datatype)));
  h.type = *type;
}

void require_finite(const char* field, double value, const std::string& what) {
  if (!std::isfinite(value))
    throw Error(fmt::format("{}: {} is {}, not a finite number", what, field, value));
}

// The placement fields nifticlib turns into 0 when they are not finite: refused instead.
void check_placement_fields(const NiftiHeader& h, const std::string& what) {
  static const char* const rows[3] = {"srow_x", "srow_y", "srow_z"};
  if (h.sform_code > 0)
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 4; ++k)
        require_finite(fmt::format("{}[{}]", rows[r], k).c_str(), h.srow[r][k], what);
  if (h.qform_code > 0) {
    require_finite("quatern_b", h.quatern_b, what);
    require_finite("quatern_c", h.quatern_c, what);
    require_finite("quatern_d", h.quatern_d, what);
    require_finite("qoffset_x", h.qoffset[0], what);
    require_finite("qoffset_y", h.qoffset[1], what);
    require_finite("qoffset_z", h.qoffset[2], what);
    for (int k = 0; k < 4; ++k)
      require_finite(fmt::format("pixdim[{}]", k).c_str(), h.pixdim[k], what);
  }
}

// NIfTI's scaling, as nibabel applies it: a slope of 0 or one not finite means none, and a
// slope in use with an intercept not finite is an error (nifticlib would make it 0).
void nifti_scaling(NiftiHeader& h, double slope, double inter, const std::string& what) {
  if (slope == 0.0 || !std::isfinite(slope)) return;
  if (!std::isfinite(inter))
    throw Error(fmt::format("{}: scl_inter is {}, not a finite number (scl_slope is {})", what,
                            inter, slope));
  h.slope = slope;
  h.inter = inter;
}

// SPM2's scaling of Analyze data (spm_vol_ana.m), which nibabel.load applies to a .hdr with no
// NIfTI magic (it reads it as Spm2AnalyzeImage): funused1 is a scale factor and funused2 an
// intercept; without a usable factor, the calibrated range over the stored one.
void analyze_scaling(NiftiHeader& h, const Fields& f) {
  const double slope = f.get<float>(IMX_N1(scl_slope));  // funused1
  if (std::isfinite(slope) && slope != 0.0) {
    const double inter = f.get<float>(IMX_N1(scl_inter));  // funused2
    h.slope = slope;
    h.inter = std::isfinite(inter) ? inter : 0.0;
    return;
  }
  const double glmax = f.get<int32_t>(IMX_N1(glmax)), glmin = f.get<int32_t>(IMX_N1(glmin));
  const double cal_max = f.get<float>(IMX_N1(cal_max)), cal_min = f.get<float>(IMX_N1(cal_min));
  const double stored = glmax - glmin, calibrated = cal_max - cal_min;
  if (stored != 0.0 && calibrated != 0.0 && std::isfinite(calibrated)) {
    h.slope = calibrated / stored;
    h.inter = cal_min - h.slope * glmin;
  }
}

void decode_348(const Fields& f, bool pair, NiftiHeader& h, const std::string& what) {
  h.ndim = f.get<int16_t>(IMX_N1(dim));
  for (int d = 1; d < 8; ++d) h.dim[d] = f.get<int16_t>(IMX_N1(dim) + 2 * d);
  check_dims(h, what);
  h.datatype = f.get<int16_t>(IMX_N1(datatype));
  check_datatype(h, what);
  for (int d = 0; d < 8; ++d) h.pixdim[d] = f.get<float>(IMX_N1(pixdim) + 4 * d);

  // nifticlib reads a single-file image with a vox_offset inside the header from byte 348, and
  // turns non-finite placement into 0: both are refused here instead.
  const float offset = f.get<float>(IMX_N1(vox_offset));
  const float lowest = pair ? 0.0f : 352.0f;
  if (!(offset >= lowest && offset < 2147483648.0f))
    throw Error(pair ? fmt::format("{}: vox_offset is {}; the voxels' offset into the .img must "
                                   "be 0 to 2^31 bytes",
                                   what, offset)
                     : fmt::format("{}: vox_offset is {}; a .nii file's data starts at byte 352 "
                                   "or later",
                                   what, offset));
  h.vox_offset = static_cast<uint64_t>(offset);  // a fraction is dropped, as nifticlib does

  if (h.kind == NiftiKind::analyze) {
    analyze_scaling(h, f);
    for (int a = 0; a < 3; ++a) h.spm_origin[a] = f.get<int16_t>(kAnalyzeOrigin + 2 * a);
    return;
  }
  h.xyzt_units = f.get<uint8_t>(IMX_N1(xyzt_units));
  h.intent_code = f.get<int16_t>(IMX_N1(intent_code));
  h.qform_code = f.get<int16_t>(IMX_N1(qform_code));
  h.sform_code = f.get<int16_t>(IMX_N1(sform_code));
  h.quatern_b = f.get<float>(IMX_N1(quatern_b));
  h.quatern_c = f.get<float>(IMX_N1(quatern_c));
  h.quatern_d = f.get<float>(IMX_N1(quatern_d));
  h.qoffset = {f.get<float>(IMX_N1(qoffset_x)), f.get<float>(IMX_N1(qoffset_y)),
               f.get<float>(IMX_N1(qoffset_z))};
  const size_t rows[3] = {IMX_N1(srow_x), IMX_N1(srow_y), IMX_N1(srow_z)};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 4; ++k) h.srow[r][k] = f.get<float>(rows[r] + 4 * k);
  check_placement_fields(h, what);
  nifti_scaling(h, f.get<float>(IMX_N1(scl_slope)), f.get<float>(IMX_N1(scl_inter)), what);
}

void decode_540(const Fields& f, bool pair, NiftiHeader& h, const std::string& what) {
  const int64_t ndim = f.get<int64_t>(IMX_N2(dim));
  h.ndim = ndim >= 0 && ndim <= 8 ? static_cast<int>(ndim) : -1;
  if (h.ndim < 0)
    throw Error(
        fmt::format("{}: not a valid NIfTI-2 header (dim[0] is {}, expected 1 to 7)", what, ndim));
  for (int d = 1; d < 8; ++d) h.dim[d] = f.get<int64_t>(IMX_N2(dim) + 8 * d);
  check_dims(h, what);
  h.datatype = f.get<int16_t>(IMX_N2(datatype));
  check_datatype(h, what);
  for (int d = 0; d < 8; ++d) h.pixdim[d] = f.get<double>(IMX_N2(pixdim) + 8 * d);

  const int64_t offset = f.get<int64_t>(IMX_N2(vox_offset));
  const int64_t lowest = pair ? 0 : 544;  // a .nii: the 540-byte header, 4 extension bytes
  if (offset < lowest || offset > (int64_t{1} << 62))
    throw Error(pair ? fmt::format("{}: vox_offset is {}; the voxels' offset into the .img must "
                                   "be 0 or more",
                                   what, offset)
                     : fmt::format("{}: vox_offset is {}; a NIfTI-2 .nii file's data starts at "
                                   "byte 544 or later",
                                   what, offset));
  h.vox_offset = static_cast<uint64_t>(offset);

  h.xyzt_units = f.get<int32_t>(IMX_N2(xyzt_units));
  h.intent_code = f.get<int32_t>(IMX_N2(intent_code));
  h.qform_code = f.get<int32_t>(IMX_N2(qform_code));
  h.sform_code = f.get<int32_t>(IMX_N2(sform_code));
  h.quatern_b = f.get<double>(IMX_N2(quatern_b));
  h.quatern_c = f.get<double>(IMX_N2(quatern_c));
  h.quatern_d = f.get<double>(IMX_N2(quatern_d));
  h.qoffset = {f.get<double>(IMX_N2(qoffset_x)), f.get<double>(IMX_N2(qoffset_y)),
               f.get<double>(IMX_N2(qoffset_z))};
  const size_t rows[3] = {IMX_N2(srow_x), IMX_N2(srow_y), IMX_N2(srow_z)};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 4; ++k) h.srow[r][k] = f.get<double>(rows[r] + 8 * k);
  check_placement_fields(h, what);
  nifti_scaling(h, f.get<double>(IMX_N2(scl_slope)), f.get<double>(IMX_N2(scl_inter)), what);
}

// A RAS affine (rows x, y, z of [M | t]) as intermix's LPS index-to-world (column-major).
glm::dmat4 lps_from_ras(const std::array<std::array<double, 4>, 3>& ras) {
  glm::dmat4 out(1.0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) out[c][r] = (r < 2 ? -1.0 : 1.0) * ras[r][c];
  return out;
}

// A grid spacing nifticlib would use: one that is not positive (or not finite) is 1.
double spacing_or_one(double d) {
  return std::isfinite(d) && d > 0.0 ? d : 1.0;
}

// The qform (NIfTI's "method 2"), by the formula nifti1.h gives: the rotation of the unit
// quaternion (a, b, c, d), a from the other three; qfac (pixdim[0] < 0: -1) flips k.
std::array<std::array<double, 4>, 3> qform_affine(const NiftiHeader& h) {
  double b = h.quatern_b, c = h.quatern_c, d = h.quatern_d;
  double a = 1.0 - (b * b + c * c + d * d);
  if (a < 1e-7) {  // a 180-degree rotation, or rounding past it: renormalize (b, c, d)
    const double n = 1.0 / std::sqrt(b * b + c * c + d * d);
    b *= n;
    c *= n;
    d *= n;
    a = 0.0;
  } else {
    a = std::sqrt(a);
  }
  const double x = spacing_or_one(h.pixdim[1]), y = spacing_or_one(h.pixdim[2]);
  const double z = (h.pixdim[0] < 0.0 ? -1.0 : 1.0) * spacing_or_one(h.pixdim[3]);
  return {{{(a * a + b * b - c * c - d * d) * x, 2 * (b * c - a * d) * y, 2 * (b * d + a * c) * z,
            h.qoffset[0]},
           {2 * (b * c + a * d) * x, (a * a + c * c - b * b - d * d) * y, 2 * (c * d - a * b) * z,
            h.qoffset[1]},
           {2 * (b * d - a * c) * x, 2 * (c * d + a * b) * y, (a * a + d * d - c * c - b * b) * z,
            h.qoffset[2]}}};
}

// Analyze 7.5 stores no orientation. intermix places it as nibabel.load does (Spm99AnalyzeHeader.
// get_origin_affine, used for every .hdr without a NIfTI magic): RAS axes with x flipped (the
// "radiological" storage Analyze files were assumed to have; the header's `orient` field is
// ignored, as nibabel ignores it), spacings from pixdim, and the origin at SPM's "originator"
// voxel (1-based) when it is set and within twice the grid, else at the centre of the grid,
// (dims - 1) / 2. A pixdim of 0 or not finite counts as 1, where nibabel's affine would be
// singular. SPM's .mat sidecar, which nibabel would apply, is refused by the reader.
std::array<std::array<double, 4>, 3> analyze_affine(const NiftiHeader& h) {
  double zoom[3], centre[3];
  bool use_origin = false, origin_sane = true;
  for (int a = 0; a < 3; ++a) {
    const double p = h.pixdim[a + 1];
    zoom[a] = std::isfinite(p) && p != 0.0 ? p : 1.0;
    const double o = h.spm_origin[a], n = static_cast<double>(h.dim[a + 1]);
    use_origin = use_origin || o != 0.0;
    origin_sane = origin_sane && o > -n && o < 2.0 * n;
  }
  zoom[0] = -zoom[0];
  for (int a = 0; a < 3; ++a)
    centre[a] = use_origin && origin_sane ? h.spm_origin[a] - 1.0
                                          : (static_cast<double>(h.dim[a + 1]) - 1.0) / 2.0;
  return {{{zoom[0], 0.0, 0.0, -centre[0] * zoom[0]},
           {0.0, zoom[1], 0.0, -centre[1] * zoom[1]},
           {0.0, 0.0, zoom[2], -centre[2] * zoom[2]}}};
}

}  // namespace

const char* nifti_kind_name(NiftiKind kind) {
  switch (kind) {
    case NiftiKind::nifti1:
      return "NIfTI-1";
    case NiftiKind::nifti2:
      return "NIfTI-2";
    case NiftiKind::analyze:
      return "Analyze 7.5";
  }
  return "NIfTI";
}

NiftiHeader decode_nifti_header(std::string_view head, bool pair, bool gzipped,
                                const std::string& what) {
  auto too_short = [&](size_t want, const char* kind) {
    if (gzipped)
      return Error(
          fmt::format("{}: corrupt or truncated gzip data: {} of the {} header bytes "
                      "inflate",
                      what, head.size(), want));
    return Error(fmt::format("{}: too short for a {} header ({} of {} bytes)", what, kind,
                             head.size(), want));
  };
  // Gzip data that stops before any header could end is cut or corrupt, whatever it holds.
  if (head.size() < 4 || (gzipped && head.size() < 348))
    throw too_short(348, pair ? "NIfTI or Analyze 7.5" : "NIfTI-1");
  // sizeof_hdr tells the version and the byte order (nibabel's test; Analyze has no magic).
  int32_t stored;
  std::memcpy(&stored, head.data(), 4);
  const auto swapped = static_cast<int32_t>(__builtin_bswap32(static_cast<uint32_t>(stored)));
  const int32_t size = stored == 348 || stored == 540     ? stored
                       : swapped == 348 || swapped == 540 ? swapped
                                                          : 0;
  if (size == 0)
    throw Error(fmt::format("{}: not a {} file (sizeof_hdr is {}, expected 348 or 540)", what,
                            pair ? "NIfTI or Analyze 7.5" : "NIfTI", stored));
  if (head.size() < static_cast<size_t>(size))
    throw too_short(static_cast<size_t>(size), size == 540 ? "NIfTI-2"
                                               : pair      ? "NIfTI-1 or Analyze 7.5"
                                                           : "NIfTI-1");

  NiftiHeader h;
  h.swapped = stored != size;
  const Fields f(head, h.swapped);
  if (size == 540) {
    check_magic(head.substr(IMX_N2(magic), 8), 540, pair, h, what);
    decode_540(f, pair, h, what);
  } else {
    check_magic(head.substr(IMX_N1(magic), 4), 348, pair, h, what);
    decode_348(f, pair, h, what);
  }
  return h;
}

glm::dmat4 nifti_index_to_world(const NiftiHeader& h) {
  if (h.kind == NiftiKind::analyze) return lps_from_ras(analyze_affine(h));
  if (h.sform_code > 0) return lps_from_ras(h.srow);
  if (h.qform_code > 0) return lps_from_ras(qform_affine(h));
  // Neither: NIfTI's "method 1", pixdim scaling only (unset pixdim: unit spacing).
  std::array<std::array<double, 4>, 3> m{};
  for (int a = 0; a < 3; ++a) m[a][a] = spacing_or_one(h.pixdim[a + 1]);
  return lps_from_ras(m);
}

std::string cifti_needs_surfaces(const std::string& what) {
  const std::string name = std::filesystem::path(what).filename().string();
  return fmt::format(
      "{} is a CIFTI-2 file of surface data: give it after its surfaces (intermix "
      "render fs_LR.32k.L.inflated.surf.gii {})",
      what, name.empty() ? what : name);
}

}  // namespace imx::detail
