#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/math.hpp"
#include "intermix/error.hpp"
#include "intermix/volume.hpp"

namespace imx {

const char* voxel_type_name(VoxelType type) {
  switch (type) {
    case VoxelType::u8:
      return "uint8";
    case VoxelType::i16:
      return "int16";
    case VoxelType::u16:
      return "uint16";
    case VoxelType::f32:
      return "float32";
  }
  return "unknown";
}

size_t VolumeData::voxel_count() const {
  if (dims.x <= 0 || dims.y <= 0 || dims.z <= 0) return 0;
  return static_cast<size_t>(dims.x) * dims.y * dims.z;
}

glm::dvec3 VolumeData::spacing() const {
  return {glm::length(glm::dvec3(index_to_world[0])), glm::length(glm::dvec3(index_to_world[1])),
          glm::length(glm::dvec3(index_to_world[2]))};
}

double VolumeData::value_at(int i, int j, int k) const {
  size_t idx = (static_cast<size_t>(k) * dims.y + j) * dims.x + i;
  return std::visit([idx](const auto& v) { return static_cast<double>(v[idx]); }, voxels);
}

std::pair<double, double> VolumeData::range() const {
  return std::visit(
      [](const auto& v) {
        if (v.empty()) return std::pair<double, double>{0.0, 0.0};
        auto [lo, hi] = std::minmax_element(v.begin(), v.end());
        return std::pair<double, double>{static_cast<double>(*lo), static_cast<double>(*hi)};
      },
      voxels);
}

void VolumeData::validate(const std::string& what) const {
  if (dims.x <= 0 || dims.y <= 0 || dims.z <= 0)
    throw Error(
        fmt::format("{}: dimensions {}x{}x{} must all be positive", what, dims.x, dims.y, dims.z));
  size_t stored = std::visit([](const auto& v) { return v.size(); }, voxels);
  if (stored != voxel_count())
    throw Error(fmt::format("{}: holds {} voxels, dimensions {}x{}x{} need {}", what, stored,
                            dims.x, dims.y, dims.z, voxel_count()));
  if (!all_finite(index_to_world))
    throw Error(fmt::format("{}: the index-to-world transform has a non-finite entry", what));
  if (std::abs(glm::determinant(glm::dmat3(index_to_world))) < 1e-12)
    throw Error(fmt::format("{}: the index-to-world transform is singular", what));
}

}  // namespace imx
