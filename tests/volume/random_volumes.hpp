// Random volumes, transfer functions and rays for the volume tests.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <variant>
#include <vector>

#include "core/ray.hpp"
#include "intermix/scene.hpp"
#include "intermix/volume.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/volume_acceleration.hpp"

namespace imx::test {

// A few Gaussian blobs on a zero background plus noise: bricks range from constant to busy.
// `scale` and `offset` map the [0, 255] field to the stored type's values.
template <class T>
VolumeData blob_volume(glm::ivec3 dims, std::mt19937& rng, float scale = 1.0f, float offset = 0.0f,
                       int blobs = 4) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  struct Blob {
    glm::vec3 c;
    float r, h;
  };
  std::vector<Blob> bs;
  for (int n = 0; n < blobs; ++n)
    bs.push_back({glm::vec3(u(rng), u(rng), u(rng)) * glm::vec3(dims),
                  2.0f + u(rng) * 0.25f * static_cast<float>(dims.x), 80.0f + 170.0f * u(rng)});
  std::vector<T> data;
  data.reserve(static_cast<size_t>(dims.x) * dims.y * dims.z);
  for (int k = 0; k < dims.z; ++k)
    for (int j = 0; j < dims.y; ++j)
      for (int i = 0; i < dims.x; ++i) {
        float v = 0.0f;
        for (const Blob& b : bs) {
          glm::vec3 d = glm::vec3(i, j, k) - b.c;
          v += b.h * std::exp(-glm::dot(d, d) / (b.r * b.r));
        }
        v = std::min(v + (u(rng) < 0.02f ? 40.0f * u(rng) : 0.0f), 255.0f);
        data.push_back(static_cast<T>(v * scale + offset));
      }
  VolumeData vol;
  vol.dims = dims;
  vol.voxels = std::move(data);
  return vol;
}

// A float volume's statistical-map mask: voxels below `below` become no data (NaN, +inf and -inf
// in turn), and so do about 1% of the others, scattered (holes inside the data), and voxel 0.
inline void punch_no_data(VolumeData& vol, std::mt19937& rng, float below) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float kinds[3] = {std::numeric_limits<float>::quiet_NaN(),
                          std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity()};
  float* v = std::get<VoxelBuffer<float>>(vol.voxels).mutable_data();
  for (size_t n = 0; n < vol.voxel_count(); ++n)
    if (n == 0 || v[n] < below || u(rng) < 0.01f) v[n] = kinds[n % 3];
}

// Sorted points over [lo, hi] whose alpha is zero at about half of them, including the first.
inline TransferFunction random_tf(std::mt19937& rng, float lo, float hi) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int count = 2 + static_cast<int>(u(rng) * 6);
  std::vector<float> at;
  for (int n = 0; n < count; ++n) at.push_back(lo + (hi - lo) * u(rng));
  std::sort(at.begin(), at.end());
  TransferFunction tf;
  for (int n = 0; n < count; ++n) {
    float a = (n == 0 || u(rng) < 0.5f) ? 0.0f : u(rng);
    tf.points.push_back({at[n], glm::vec4(u(rng), u(rng), u(rng), a)});
  }
  tf.unit_distance = 0.5 + u(rng);
  return tf;
}

// A ray in a random direction through a random point of the cube of side `radius` around
// `centre`, starting well outside it.
inline Ray random_ray(std::mt19937& rng, glm::vec3 centre, float radius) {
  std::normal_distribution<float> n(0.0f, 1.0f);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f);
  glm::vec3 d = glm::normalize(glm::vec3(n(rng), n(rng), n(rng)));
  glm::vec3 target = centre + radius * glm::vec3(u(rng), u(rng), u(rng));
  return Ray{target - 3.0f * radius * d, d};
}

// `obj` made ready to march at `step` with the structures `settings` asks for.
inline PreparedVolume prepared(const VolumeObject& obj, float step, const MarchSettings& settings) {
  PreparedVolume v(obj);
  v.accel = accelerate(obj, v.lut, step, settings);
  return v;
}

}  // namespace imx::test
