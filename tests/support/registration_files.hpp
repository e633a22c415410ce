// A known placement (rotation, anisotropic scale, translation) written as each registration
// tool writes it, by conversions computed here from each format's definition, not by the readers.
#pragma once
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace imx::test {

// The moving image's placement in the fixed image's space (LPS mm): what every file encodes.
inline glm::dmat4 known_placement() {
  const glm::dmat4 r = glm::rotate(glm::dmat4(1.0), glm::radians(23.0), glm::dvec3(0, 0, 1)) *
                       glm::rotate(glm::dmat4(1.0), glm::radians(-11.0), glm::dvec3(1, 0, 0)) *
                       glm::rotate(glm::dmat4(1.0), glm::radians(37.0), glm::dvec3(0, 1, 0));
  const glm::dmat4 s = glm::scale(glm::dmat4(1.0), glm::dvec3(1.1, 0.9, 1.3));
  return glm::translate(glm::dmat4(1.0), glm::dvec3(12.5, -7.25, 30.0)) * r * s;
}

// RAS <-> LPS: diag(-1, -1, 1).
inline glm::dmat4 flip_xy() {
  glm::dmat4 f(1.0);
  f[0][0] = f[1][1] = -1.0;
  return f;
}

// The first three rows of `m`, 4 numbers each, row by row.
inline std::vector<double> rows_of(const glm::dmat4& m) {
  std::vector<double> v;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) v.push_back(m[c][r]);
  return v;
}

inline std::string joined(const std::vector<double>& v) {
  std::string s;
  for (double x : v) s += fmt::format("{}{:.17g}", s.empty() ? "" : " ", x);
  return s;
}

// ITK's parameters of the map `fixed_to_moving` with centre c: 9 matrix entries row by row and
// the translation t, where T(x) = A (x - c) + c + t, so t = offset - c + A c.
inline std::vector<double> itk_affine_parameters(const glm::dmat4& fixed_to_moving,
                                                 const glm::dvec3& c) {
  const glm::dmat3 a(fixed_to_moving);
  const glm::dvec3 offset(fixed_to_moving[3]);
  const glm::dvec3 t = offset - c + a * c;
  std::vector<double> p;
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 3; ++col) p.push_back(a[col][r]);
  p.insert(p.end(), {t.x, t.y, t.z});
  return p;
}

inline std::string itk_text(const std::string& type, const std::vector<double>& parameters,
                            const std::vector<double>& fixed) {
  return fmt::format(
      "#Insight Transform File V1.0\n#Transform 0\nTransform: {}\nParameters: {}\n"
      "FixedParameters: {}\n",
      type, joined(parameters), joined(fixed));
}

// One MATLAB v4 column vector as vnl_matlab_write writes it: type (0 double / 10 single, plus
// 1000 big-endian), rows, 1 column, no imaginary part, the name's length with its NUL.
inline std::string matlab_v4_vector(const std::string& name, const std::vector<double>& values,
                                    bool single = false, bool big_endian = false) {
  std::string out;
  auto put32 = [&](uint32_t v) {
    if (big_endian) v = __builtin_bswap32(v);
    out.append(reinterpret_cast<const char*>(&v), 4);
  };
  put32((big_endian ? 1000u : 0u) + (single ? 10u : 0u));
  put32(static_cast<uint32_t>(values.size()));
  put32(1);
  put32(0);
  put32(static_cast<uint32_t>(name.size() + 1));
  out += name;
  out += '\0';
  for (double v : values) {
    if (single) {
      put32(std::bit_cast<uint32_t>(static_cast<float>(v)));
    } else {
      uint64_t u = std::bit_cast<uint64_t>(v);
      if (big_endian) u = __builtin_bswap64(u);
      out.append(reinterpret_cast<const char*>(&u), 8);
    }
  }
  return out;
}

// FSL's scaled voxels of an image with `dims`, voxel size `size`, the first axis flipped when
// its sform's determinant is positive: x = (nx - 1 - i) dx.
inline glm::dmat4 fsl_scaled(const glm::ivec3& dims, const glm::dvec3& size, bool flipped) {
  glm::dmat4 s(1.0);
  s[0][0] = size.x;
  s[1][1] = size.y;
  s[2][2] = size.z;
  if (flipped) {
    s[0][0] = -size.x;
    s[3][0] = (dims.x - 1) * size.x;
  }
  return s;
}

// FreeSurfer's voxel-to-RAS of a volume info block (what nibabel's MGHHeader.get_affine gives):
// [Mdc diag(size) | c - Mdc diag(size) dims / 2].
inline glm::dmat4 freesurfer_vox2ras(const glm::dvec3& dims, const glm::dvec3& size,
                                     const glm::dmat3& directions, const glm::dvec3& centre) {
  glm::dmat3 axes = directions;
  for (int a = 0; a < 3; ++a) axes[a] *= size[a];
  glm::dmat4 m(axes);
  m[3] = glm::dvec4(centre - axes * (dims / 2.0), 1.0);
  return m;
}

inline std::string lta_text(int type, const glm::dmat4& m, const std::string& src_block,
                            const std::string& dst_block) {
  std::string rows;
  for (int r = 0; r < 4; ++r)
    rows += fmt::format("{:.17g} {:.17g} {:.17g} {:.17g}\n", m[0][r], m[1][r], m[2][r], m[3][r]);
  return fmt::format(
      "# transform file reg.lta\n# created by test\ntype      = {} # {}\nnxforms   = 1\n"
      "mean      = 0.0000 0.0000 0.0000\nsigma     = 1.0000\n1 4 4\n{}src volume info\n{}"
      "dst volume info\n{}subject test\nfscale 0.100000\n",
      type, type == 0 ? "LINEAR_VOX_TO_VOX" : "LINEAR_RAS_TO_RAS", rows, src_block, dst_block);
}

inline std::string lta_volume_block(const glm::dvec3& dims, const glm::dvec3& size,
                                    const glm::dmat3& directions, const glm::dvec3& centre) {
  return fmt::format(
      "valid = 1  # volume info valid\nfilename = vol.nii.gz\nvolume = {} {} {}\n"
      "voxelsize = {:.15e} {:.15e} {:.15e}\nxras   = {:.15e} {:.15e} {:.15e}\n"
      "yras   = {:.15e} {:.15e} {:.15e}\nzras   = {:.15e} {:.15e} {:.15e}\n"
      "cras   = {:.15e} {:.15e} {:.15e}\n",
      dims.x, dims.y, dims.z, size.x, size.y, size.z, directions[0].x, directions[0].y,
      directions[0].z, directions[1].x, directions[1].y, directions[1].z, directions[2].x,
      directions[2].y, directions[2].z, centre.x, centre.y, centre.z);
}

// A displacement field as ITK writes one: a NIfTI-1 of dims x, y, z, 1, 3, intent 1007
// (vector), float32, the sform `index_to_world_lps` (stored RAS), and the vector of each voxel
// (LPS mm) from `vector(i, j, k)`. Written byte by byte from the NIfTI-1 header layout.
template <class Vector>
std::string displacement_field_nifti(const glm::ivec3& dims, const glm::dmat4& index_to_world_lps,
                                     Vector vector, int intent = 1007) {
  std::string h(352, '\0');
  auto put = [&](size_t at, auto value) { std::memcpy(h.data() + at, &value, sizeof(value)); };
  put(0, int32_t{348});
  const int16_t dim[8] = {5,
                          static_cast<int16_t>(dims.x),
                          static_cast<int16_t>(dims.y),
                          static_cast<int16_t>(dims.z),
                          1,
                          3,
                          1,
                          1};
  for (int k = 0; k < 8; ++k) put(40 + 2 * static_cast<size_t>(k), dim[k]);
  put(68, static_cast<int16_t>(intent));
  put(70, int16_t{16});  // float32
  put(72, int16_t{32});
  const glm::dmat4 ras = flip_xy() * index_to_world_lps;
  for (int a = 0; a < 3; ++a)
    put(76 + 4 * static_cast<size_t>(a + 1), static_cast<float>(glm::length(glm::dvec3(ras[a]))));
  put(76, 1.0f);         // qfac
  put(108, 352.0f);      // vox_offset
  put(123, uint8_t{2});  // mm
  put(254, int16_t{2});  // sform_code: aligned
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      put(280 + 16 * static_cast<size_t>(r) + 4 * static_cast<size_t>(c),
          static_cast<float>(ras[c][r]));
  std::memcpy(h.data() + 344, "n+1\0", 4);
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < dims.z; ++k)
      for (int j = 0; j < dims.y; ++j)
        for (int i = 0; i < dims.x; ++i) {
          const float v = static_cast<float>(vector(i, j, k)[c]);
          h.append(reinterpret_cast<const char*>(&v), 4);
        }
  return h;
}

}  // namespace imx::test
