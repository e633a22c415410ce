// Fragment: one surface crossing of one sample ray, shaded and premultiplied.
#pragma once
#include <cstdint>

#include <glm/vec4.hpp>

namespace imx {

struct Fragment {
  float t = 0.0f;             // depth along the sample's normalized ray, mm (SPEC §1)
  glm::vec4 color{0.0f};      // shaded, premultiplied RGBA
  uint32_t object = 0;        // index into Scene::order
  uint32_t front_facing = 0;  // 1 when the surface faces the viewer
};

}  // namespace imx
