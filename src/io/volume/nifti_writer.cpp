// write_nifti and write_nifti_frames: a NIfTI-1 single file (.nii, or .nii.gz) of one volume or
// of a 4-D series, its header made by nifticlib.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nifti1_io.h>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/streams/atomic_file.hpp"
#include "io/streams/gzip.hpp"

namespace imx {

namespace {

int nifti_datatype(VoxelType type) {
  switch (type) {
    case VoxelType::u8:
      return DT_UINT8;
    case VoxelType::i16:
      return DT_INT16;
    case VoxelType::u16:
      return DT_UINT16;
    case VoxelType::f32:
      return DT_FLOAT32;
  }
  return DT_UNKNOWN;
}

// intermix's LPS index-to-world as NIfTI's RAS mat44 (row-major): negate the x and y rows.
mat44 to_ras(const glm::dmat4& lps) {
  mat44 m{};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m.m[r][c] = static_cast<float>((r < 2 ? -1.0 : 1.0) * lps[c][r]);
  m.m[3][0] = m.m[3][1] = m.m[3][2] = 0.0f;
  m.m[3][3] = 1.0f;
  return m;
}

// Entries of two affines agree to within NIfTI's float32 rounding (relative 1e-4 of the entry,
// at least 1e-4): frames from one series may differ by such noise.
bool same_affine(const glm::dmat4& a, const glm::dmat4& b) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!(std::abs(a[c][r] - b[c][r]) <= 1e-4 * std::max(1.0, std::abs(a[c][r])))) return false;
  return true;
}

// The bytes of a volume's voxels, in place.
std::span<const uint8_t> voxel_bytes(const VolumeData& volume) {
  return std::visit(
      [](const auto& v) {
        return std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(v.data()),
                                        v.size() * sizeof(v[0]));
      },
      volume.voxels);
}

// One file for write_nifti (a 3-D image: `series` false, one volume) and write_nifti_frames (a
// 4-D image of one or more frames, `frame_seconds` apart when > 0).
void write_nifti_file(std::span<const VolumeData> frames, bool series, double frame_seconds,
                      const std::filesystem::path& file, bool gzip) {
  const std::string what = file.string();
  if (frames.empty()) throw Error(fmt::format("{}: no frames to write", what));
  if (!std::isfinite(frame_seconds) || frame_seconds < 0.0)
    throw Error(fmt::format("{}: the time between frames is {} s; it must be 0 (unknown) or more",
                            what, frame_seconds));
  const VolumeData& first = frames[0];
  for (size_t k = 0; k < frames.size(); ++k) {
    const VolumeData& f = frames[k];
    const std::string frame_what = series ? fmt::format("{} (frame {})", what, k) : what;
    f.validate(frame_what);
    if (f.dims != first.dims)
      throw Error(fmt::format(
          "{}: frame {} has {}x{}x{} voxels, frame 0 {}x{}x{}; the frames of "
          "one file share one grid",
          what, k, f.dims.x, f.dims.y, f.dims.z, first.dims.x, first.dims.y, first.dims.z));
    if (f.type() != first.type())
      throw Error(
          fmt::format("{}: frame {} holds {} voxels, frame 0 {}; the frames of one file "
                      "share one type",
                      what, k, voxel_type_name(f.type()), voxel_type_name(first.type())));
    if (!same_affine(f.index_to_world, first.index_to_world))
      throw Error(
          fmt::format("{}: frame {} is placed otherwise than frame 0 (its index-to-world "
                      "transform differs); the frames of one file share one grid",
                      what, k));
  }
  if (series && frames.size() > static_cast<size_t>(std::numeric_limits<int16_t>::max()))
    throw Error(fmt::format("{}: {} frames; NIfTI-1 holds at most {}", what, frames.size(),
                            std::numeric_limits<int16_t>::max()));
  const int count = static_cast<int>(frames.size());
  const int dims[8] = {series ? 4 : 3, first.dims.x, first.dims.y, first.dims.z, count, 1, 1, 1};
  // data_fill 0: nifticlib allocates no voxel buffer; ours is written below.
  std::unique_ptr<nifti_image, void (*)(nifti_image*)> nim(
      nifti_make_new_nim(dims, nifti_datatype(first.type()), 0), nifti_image_free);
  if (!nim) throw Error(fmt::format("{}: nifticlib could not make a header", what));
  const mat44 ras = to_ras(first.index_to_world);
  // The sform keeps any affine exactly (a gantry tilt's shear too); the qform is its nearest
  // rotation, for readers that only know the qform.
  nim->sform_code = nim->qform_code = NIFTI_XFORM_SCANNER_ANAT;
  nim->sto_xyz = ras;
  nim->sto_ijk = nifti_mat44_inverse(ras);
  nifti_mat44_to_quatern(ras, &nim->quatern_b, &nim->quatern_c, &nim->quatern_d, &nim->qoffset_x,
                         &nim->qoffset_y, &nim->qoffset_z, &nim->dx, &nim->dy, &nim->dz,
                         &nim->qfac);
  nim->pixdim[1] = nim->dx;
  nim->pixdim[2] = nim->dy;
  nim->pixdim[3] = nim->dz;
  nim->xyz_units = NIFTI_UNITS_MM;
  if (series && frame_seconds > 0.0) {
    nim->dt = nim->pixdim[4] = static_cast<float>(frame_seconds);
    nim->time_units = NIFTI_UNITS_SEC;
  }
  nim->nifti_type = NIFTI_FTYPE_NIFTI1_1;
  std::strncpy(nim->descrip, "intermix", sizeof nim->descrip - 1);
  nifti_1_header header = nifti_convert_nim2nhdr(nim.get());
  header.vox_offset = 352.0f;  // the 348-byte header, then 4 bytes saying "no extensions"

  std::string head(352, '\0');
  std::memcpy(head.data(), &header, sizeof header);
  // The header, then each frame's voxels where they lie: no copy joins them.
  std::vector<std::span<const uint8_t>> parts;
  parts.emplace_back(reinterpret_cast<const uint8_t*>(head.data()), head.size());
  for (const VolumeData& f : frames) parts.push_back(voxel_bytes(f));
  write_file_atomically(file, [&](std::ostream& out) {
    if (!gzip) {
      for (std::span<const uint8_t> part : parts)
        out.write(reinterpret_cast<const char*>(part.data()),
                  static_cast<std::streamsize>(part.size()));
      return;
    }
    // One gzip member for header and voxels, as nifticlib's own .nii.gz files are.
    detail::gzip(parts, out, 6, what);
  });
}

}  // namespace

void write_nifti(const VolumeData& volume, const std::filesystem::path& file, bool gzip) {
  write_nifti_file(std::span<const VolumeData>(&volume, 1), false, 0.0, file, gzip);
}

void write_nifti_frames(const std::vector<VolumeData>& frames, const std::filesystem::path& file,
                        double frame_seconds, bool gzip) {
  write_nifti_file(frames, true, frame_seconds, file, gzip);
}

}  // namespace imx
