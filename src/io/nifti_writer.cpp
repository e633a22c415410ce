// write_nifti: a NIfTI-1 single file (.nii, or .nii.gz), its header made by nifticlib.
#include <cstring>
#include <memory>
#include <span>
#include <string>

#include <fmt/format.h>
#include <nifti1_io.h>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/atomic_file.hpp"
#include "io/gzip.hpp"

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
    for (int c = 0; c < 4; ++c)
      m.m[r][c] = static_cast<float>((r < 2 ? -1.0 : 1.0) * lps[c][r]);
  m.m[3][0] = m.m[3][1] = m.m[3][2] = 0.0f;
  m.m[3][3] = 1.0f;
  return m;
}

}  // namespace

void write_nifti(const VolumeData& volume, const std::filesystem::path& file, bool gzip) {
  const std::string what = file.string();
  volume.validate(what);
  const int dims[8] = {3, volume.dims.x, volume.dims.y, volume.dims.z, 1, 1, 1, 1};
  // data_fill 0: nifticlib allocates no voxel buffer; ours is written below.
  std::unique_ptr<nifti_image, void (*)(nifti_image*)> nim(
      nifti_make_new_nim(dims, nifti_datatype(volume.type()), 0), nifti_image_free);
  if (!nim) throw Error(fmt::format("{}: nifticlib could not make a header", what));
  const mat44 ras = to_ras(volume.index_to_world);
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
  nim->nifti_type = NIFTI_FTYPE_NIFTI1_1;
  std::strncpy(nim->descrip, "intermix", sizeof nim->descrip - 1);
  nifti_1_header header = nifti_convert_nim2nhdr(nim.get());
  header.vox_offset = 352.0f;  // the 348-byte header, then 4 bytes saying "no extensions"

  std::string head(352, '\0');
  std::memcpy(head.data(), &header, sizeof header);
  std::span<const uint8_t> voxels = std::visit(
      [](const auto& v) {
        return std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(v.data()),
                                        v.size() * sizeof(v[0]));
      },
      volume.voxels);
  write_file_atomically(file, [&](std::ostream& out) {
    if (!gzip) {
      out.write(head.data(), static_cast<std::streamsize>(head.size()));
      out.write(reinterpret_cast<const char*>(voxels.data()),
                static_cast<std::streamsize>(voxels.size()));
      return;
    }
    // One gzip member for header and voxels, as nifticlib's own .nii.gz files are.
    const std::span<const uint8_t> parts[] = {
        {reinterpret_cast<const uint8_t*>(head.data()), head.size()}, voxels};
    detail::gzip(parts, out, 6, what);
  });
}

}  // namespace imx
