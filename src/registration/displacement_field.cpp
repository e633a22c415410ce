// warp_volume: one resampling of the moving volume through a displacement field.
#include "registration/displacement_field.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "core/parallel.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/streams/file_head.hpp"

namespace imx {
namespace {

constexpr int kIntentVector = 1007;

struct FieldHeader {
  bool nifti = false;
  int intent = 0;
  int64_t dim[8] = {};
};

// The intent code and dims from a NIfTI-1 or NIfTI-2 header (either byte order).
FieldHeader field_header(const std::filesystem::path& file) {
  FieldHeader h;
  const detail::FileHead head = detail::read_file_head(file, 540, file.string());
  const std::string& b = head.bytes;
  if (b.size() < 348) return h;
  auto i32 = [&](size_t at, bool swap) {
    uint32_t v = 0;
    std::memcpy(&v, b.data() + at, 4);
    return static_cast<int32_t>(swap ? __builtin_bswap32(v) : v);
  };
  auto i16 = [&](size_t at, bool swap) {
    uint16_t v = 0;
    std::memcpy(&v, b.data() + at, 2);
    return static_cast<int16_t>(swap ? __builtin_bswap16(v) : v);
  };
  for (bool swap : {false, true}) {
    if (i32(0, swap) == 348 && b.compare(344, 3, "n+1") == 0) {
      h.nifti = true;
      h.intent = i16(68, swap);
      for (int k = 0; k < 8; ++k) h.dim[k] = i16(40 + 2 * static_cast<size_t>(k), swap);
      return h;
    }
    if (i32(0, swap) == 540 && b.size() >= 540 && b.compare(4, 3, "n+2") == 0) {
      h.nifti = true;
      h.intent = i32(504, swap);
      for (int k = 0; k < 8; ++k) {
        uint64_t v = 0;
        std::memcpy(&v, b.data() + 16 + 8 * static_cast<size_t>(k), 8);
        h.dim[k] = static_cast<int64_t>(swap ? __builtin_bswap64(v) : v);
      }
      return h;
    }
  }
  return h;
}

// A volume's voxels as float, for the sampling below.
std::vector<float> as_floats(const VolumeData& v) {
  return std::visit(
      [](const auto& s) {
        std::vector<float> out(s.size());
        for (size_t i = 0; i < s.size(); ++i) out[i] = static_cast<float>(s[i]);
        return out;
      },
      v.voxels);
}

// Trilinear value of `data` (dims `d`) at index position p; nullopt outside the voxel centres'
// box (a half voxel of clamping at the faces would invent data).
bool trilinear(const std::vector<float>& data, const glm::ivec3& d, const glm::dvec3& p,
               double& out) {
  const double eps = 1e-9;
  if (!(p.x >= -eps && p.y >= -eps && p.z >= -eps && p.x <= d.x - 1 + eps && p.y <= d.y - 1 + eps &&
        p.z <= d.z - 1 + eps))
    return false;
  const glm::dvec3 q = glm::clamp(p, glm::dvec3(0.0), glm::dvec3(d - 1));
  const glm::ivec3 i0 = glm::min(glm::ivec3(glm::floor(q)), glm::max(d - 2, glm::ivec3(0)));
  const glm::ivec3 i1 = glm::min(i0 + 1, d - 1);
  const glm::dvec3 f = q - glm::dvec3(i0);
  auto at = [&](int i, int j, int k) {
    return static_cast<double>(data[(static_cast<size_t>(k) * d.y + j) * d.x + i]);
  };
  const double c00 = at(i0.x, i0.y, i0.z) * (1 - f.x) + at(i1.x, i0.y, i0.z) * f.x;
  const double c10 = at(i0.x, i1.y, i0.z) * (1 - f.x) + at(i1.x, i1.y, i0.z) * f.x;
  const double c01 = at(i0.x, i0.y, i1.z) * (1 - f.x) + at(i1.x, i0.y, i1.z) * f.x;
  const double c11 = at(i0.x, i1.y, i1.z) * (1 - f.x) + at(i1.x, i1.y, i1.z) * f.x;
  out = (c00 * (1 - f.y) + c10 * f.y) * (1 - f.z) + (c01 * (1 - f.y) + c11 * f.y) * f.z;
  return true;
}

}  // namespace

bool is_displacement_field(const std::filesystem::path& file) {
  try {
    const FieldHeader h = field_header(file);
    return h.nifti && h.intent == kIntentVector;
  } catch (const std::exception&) {
    return false;
  }
}

VolumeData warp_volume(const VolumeData& moving, const std::filesystem::path& field,
                       double* seconds) {
  const std::string what = field.string();
  const FieldHeader h = field_header(field);
  if (!h.nifti || h.intent != kIntentVector)
    throw Error(
        fmt::format("{}: not a displacement field (a NIfTI with intent code 1007, "
                    "NIFTI_INTENT_VECTOR)",
                    what));
  if (h.dim[0] != 5 || h.dim[4] != 1 || h.dim[5] != 3)
    throw Error(
        fmt::format("{}: a displacement field has dims x, y, z, 1, 3 (5-D, three "
                    "components); this one has {} dimensions ({}, {}, {}, {}, {})",
                    what, h.dim[0], h.dim[1], h.dim[2], h.dim[3], h.dim[4], h.dim[5]));
  // The three components are the file's three frames (read_volume's dim[5] components).
  VolumeData component[3];
  std::vector<float> d[3];
  for (int c = 0; c < 3; ++c) {
    component[c] = read_volume(field, c);
    d[c] = as_floats(component[c]);
    for (float x : d[c])
      if (!std::isfinite(x))
        throw Error(fmt::format("{}: component {} has a non-finite vector entry", what, c));
  }
  const glm::ivec3 fd = component[0].dims;
  const glm::dmat4 world_to_field = glm::inverse(component[0].index_to_world);
  const glm::dmat4 world_to_moving = glm::inverse(moving.index_to_world);
  const std::vector<float> m = as_floats(moving);
  const auto start = std::chrono::steady_clock::now();
  VolumeData out;
  out.dims = moving.dims;
  out.index_to_world = moving.index_to_world;
  std::vector<float> values(moving.voxel_count());
  const glm::ivec3 md = moving.dims;
  parallel_for(md.z, 0, [&](long z0, long z1) {
    for (long k = z0; k < z1; ++k)
      for (int j = 0; j < md.y; ++j)
        for (int i = 0; i < md.x; ++i) {
          const glm::dvec3 x = glm::dvec3(moving.index_to_world * glm::dvec4(i, j, k, 1.0));
          const glm::dvec3 fp = glm::dvec3(world_to_field * glm::dvec4(x, 1.0));
          glm::dvec3 disp(0.0);  // zero outside the field, as ITK
          double v = 0.0;
          if (trilinear(d[0], fd, fp, v)) {
            disp.x = v;
            trilinear(d[1], fd, fp, disp.y);
            trilinear(d[2], fd, fp, disp.z);
          }
          const glm::dvec3 mp = glm::dvec3(world_to_moving * glm::dvec4(x + disp, 1.0));
          double value = 0.0;
          values[(static_cast<size_t>(k) * md.y + j) * md.x + i] =
              trilinear(m, md, mp, value) ? static_cast<float>(value)
                                          : std::numeric_limits<float>::quiet_NaN();
        }
  });
  out.voxels = VoxelBuffer<float>(std::move(values));
  if (seconds != nullptr)
    *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace imx
