// Colour volumes (VolumeData::colours): the scalar that stands for a voxel's colour, and the
// colour of a sample, which every method and plane shows instead of the TF's colour and the grey.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

#include "core/colour.hpp"
#include "intermix/volume.hpp"
#include "volume/voxel_grid.hpp"

namespace imx {

// The scalar of an RGB voxel: its luminance with NiiVue's weights for an RGB volume's opacity
// (0.21 R + 0.72 G + 0.07 B, close to Rec. 709), rounded; black is 0 and white 255.
inline uint8_t colour_luminance(uint8_t r, uint8_t g, uint8_t b) {
  return static_cast<uint8_t>((21u * r + 72u * g + 7u * b + 50u) / 100u);
}

// The linear value of each sRGB-encoded byte, so that colours interpolate as light does.
inline const std::array<float, 256>& srgb_byte_to_linear() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[static_cast<size_t>(i)] = srgb_decode(i / 255.0f);
    return t;
  }();
  return table;
}

// A non-owning view of a volume's colours; inactive for a scalar volume.
struct ColourGrid {
  const uint8_t* rgb = nullptr;
  glm::ivec3 dims{0};
  const float* linear = nullptr;  // srgb_byte_to_linear()

  ColourGrid() = default;
  explicit ColourGrid(const VolumeData& data)
      : rgb(data.colours ? data.colours->rgb.data() : nullptr),
        dims(data.dims),
        linear(srgb_byte_to_linear().data()) {}

  bool active() const { return rgb != nullptr; }

  // Linear RGB in [0, 1] at index-space position p: the trilinear interpolation of the eight
  // voxels around it, clamped to the grid as VoxelGrid::sample clamps.
  glm::vec3 sample(glm::vec3 p) const {
    const glm::vec3 hi = glm::vec3(dims - 1);
    p = {VoxelGrid<uint8_t>::clamp_index(p.x, hi.x), VoxelGrid<uint8_t>::clamp_index(p.y, hi.y),
         VoxelGrid<uint8_t>::clamp_index(p.z, hi.z)};
    const glm::ivec3 i0 = glm::min(glm::ivec3(p), glm::max(dims - 2, glm::ivec3(0)));
    const glm::vec3 f = p - glm::vec3(i0);
    const size_t sy = static_cast<size_t>(dims.x), sz = sy * static_cast<size_t>(dims.y);
    const size_t dx = dims.x > 1 ? 1 : 0, dy = dims.y > 1 ? sy : 0, dz = dims.z > 1 ? sz : 0;
    const size_t base = i0.z * sz + i0.y * sy + i0.x;
    auto at = [&](size_t offset) {
      const uint8_t* c = rgb + 3 * (base + offset);
      return glm::vec3(linear[c[0]], linear[c[1]], linear[c[2]]);
    };
    const glm::vec3 c00 = glm::mix(at(0), at(dx), f.x), c10 = glm::mix(at(dy), at(dy + dx), f.x);
    const glm::vec3 c01 = glm::mix(at(dz), at(dz + dx), f.x);
    const glm::vec3 c11 = glm::mix(at(dz + dy), at(dz + dy + dx), f.x);
    return glm::mix(glm::mix(c00, c10, f.y), glm::mix(c01, c11, f.y), f.z);
  }
};

}  // namespace imx
