// AnyGrid: a voxel view whose type is chosen at run time (one predictable switch per sample).
#pragma once
#include <variant>

#include "intermix/volume.hpp"
#include "volume/voxel_grid.hpp"

namespace imx {

struct AnyGrid {
  VoxelType type = VoxelType::u8;
  const void* data = nullptr;
  glm::ivec3 dims{0};

  explicit AnyGrid(const VolumeData& v)
      : type(v.type()),
        data(
            std::visit([](const auto& s) { return static_cast<const void*>(s.data()); }, v.voxels)),
        dims(v.dims) {}

  template <class T>
  VoxelGrid<T> as() const {
    return VoxelGrid<T>{static_cast<const T*>(data), dims};
  }

  // Calls fn(VoxelGrid<T>) with the grid's native type.
  template <class Fn>
  decltype(auto) visit(Fn&& fn) const {
    switch (type) {
      case VoxelType::u8:
        return fn(as<uint8_t>());
      case VoxelType::i16:
        return fn(as<int16_t>());
      case VoxelType::u16:
        return fn(as<uint16_t>());
      default:
        return fn(as<float>());
    }
  }

  float sample(glm::vec3 p) const {
    return visit([&](const auto& g) { return g.sample(p); });
  }
  glm::vec3 gradient(glm::vec3 p) const {
    return visit([&](const auto& g) { return g.gradient(p); });
  }
  glm::vec3 gradient_of_data(glm::vec3 p) const {
    return visit([&](const auto& g) { return g.gradient_of_data(p); });
  }
  bool inside(glm::vec3 p) const { return as<uint8_t>().inside(p); }
};

}  // namespace imx
