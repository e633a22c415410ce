// A test volume with a closed-form answer: 21^3 voxels of value 1 filling [-10, 10]^3 mm.
#pragma once
#include <memory>

#include <glm/gtc/matrix_transform.hpp>

#include "intermix/scene.hpp"

namespace imx::test {

inline VolumeObject homogeneous_volume(float alpha_per_mm, glm::vec3 rgb) {
  VolumeObject v;
  v.name = "fog";
  auto data = std::make_shared<VolumeData>();
  data->dims = {21, 21, 21};
  data->voxels = std::vector<float>(21 * 21 * 21, 1.0f);
  v.data = data;
  v.index_to_world = glm::translate(glm::dmat4(1.0), glm::dvec3(-10.0));
  v.transfer_function.points = {{0.0, glm::vec4(rgb, alpha_per_mm)}};
  return v;
}

}  // namespace imx::test
