// Helpers for the rasterizer tests: hand-built scenes, meshes and whole-frame rasterization.
#pragma once
#include <cmath>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/camera_model.hpp"
#include "core/parallel.hpp"
#include "intermix/scene.hpp"
#include "raster/rasterizer.hpp"

namespace imx::test {

inline std::vector<glm::vec2> grid_offsets(int n) {
  std::vector<glm::vec2> out;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) out.emplace_back((i + 0.5f) / n, (j + 0.5f) / n);
  return out;
}

inline Scene make_scene(int width, int height, Projection projection = Projection::perspective) {
  Scene s;
  s.image.width = width;
  s.image.height = height;
  s.camera.projection = projection;
  return s;  // default camera: eye (0,-600,0), target 0, up +z, fov 30, ortho height 200
}

inline void add_mesh(Scene& scene, Mesh mesh, Material material = {}, std::string name = "mesh") {
  MeshObject m;
  m.name = std::move(name);
  m.mesh = std::make_shared<const Mesh>(std::move(mesh));
  m.material = material;
  scene.order.push_back({ObjectKind::mesh, static_cast<int>(scene.meshes.size())});
  scene.meshes.push_back(std::move(m));
}

inline void add_plane(Scene& scene, PlaneObject plane) {
  scene.order.push_back({ObjectKind::plane, static_cast<int>(scene.planes.size())});
  scene.planes.push_back(std::move(plane));
}

// A quad from two triangles (a, b, c) and (a, c, d), sharing the diagonal a-c.
inline Mesh quad(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
  Mesh m;
  m.positions = {a, b, c, d};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

// An axis-aligned box with outward-facing (counter-clockwise seen from outside) triangles.
inline Mesh box(glm::vec3 lo, glm::vec3 hi) {
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.emplace_back(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
  const unsigned faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& f : faces) {
    m.triangles.push_back({f[0], f[1], f[2]});
    m.triangles.push_back({f[0], f[2], f[3]});
  }
  return m;
}

// A closed UV sphere, outward winding, with vertex normals.
inline Mesh sphere(glm::vec3 centre, float radius, int rings, int segments) {
  Mesh m;
  const float pi = 3.14159265358979f;
  m.positions.push_back(centre + glm::vec3(0, 0, radius));
  m.normals.emplace_back(0, 0, 1);
  for (int r = 1; r < rings; ++r) {
    float theta = pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      float phi = 2.0f * pi * s / segments;
      glm::vec3 n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                  std::cos(theta));
      m.positions.push_back(centre + radius * n);
      m.normals.push_back(n);
    }
  }
  m.positions.push_back(centre - glm::vec3(0, 0, radius));
  m.normals.emplace_back(0, 0, -1);
  const unsigned south = static_cast<unsigned>(m.positions.size() - 1);
  auto ring = [&](int r, int s) { return 1u + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) m.triangles.push_back({0, ring(1, s), ring(1, s + 1)});
  for (int r = 1; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      m.triangles.push_back({ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)});
      m.triangles.push_back({ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)});
    }
  for (int s = 0; s < segments; ++s)
    m.triangles.push_back({south, ring(rings - 1, s + 1), ring(rings - 1, s)});
  return m;
}

// Every sample's fragments of a whole frame: index ((y * width) + x) * spp + s.
struct FrameFragments {
  int width = 0, height = 0, spp = 0;
  std::vector<std::vector<Fragment>> samples;
  const std::vector<Fragment>& at(int x, int y, int s) const {
    return samples[(static_cast<size_t>(y) * width + x) * spp + s];
  }
};

inline FrameFragments rasterize_frame(const Rasterizer& r, const CameraModel& camera,
                                      std::span<const glm::vec2> offsets) {
  FrameFragments f;
  f.width = camera.width();
  f.height = camera.height();
  f.spp = static_cast<int>(offsets.size());
  f.samples.resize(static_cast<size_t>(f.width) * f.height * f.spp);
  const int ts = r.tile_size();
  SampleFragments out;
  for (int y0 = 0; y0 < f.height; y0 += ts)
    for (int x0 = 0; x0 < f.width; x0 += ts) {
      TileRect tile{x0, y0, std::min(x0 + ts, f.width), std::min(y0 + ts, f.height)};
      r.rasterize(tile, offsets, out);
      size_t i = 0;
      for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x)
          for (int s = 0; s < f.spp; ++s, ++i) {
            auto frags = out.of(i);
            f.samples[(static_cast<size_t>(y) * f.width + x) * f.spp + s].assign(frags.begin(),
                                                                                 frags.end());
          }
    }
  return f;
}

}  // namespace imx::test
