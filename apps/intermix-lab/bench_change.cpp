#include "bench_change.hpp"

#include <chrono>

#include "intermix/renderer.hpp"

namespace imx::cli {

namespace {

// Reloading a scene makes new data; equal data become the same objects again.
void share_unchanged_data(Scene& edited, const Scene& base) {
  for (size_t i = 0; i < edited.volumes.size() && i < base.volumes.size(); ++i) {
    const VolumeData &a = *edited.volumes[i].data, &b = *base.volumes[i].data;
    if (a.dims == b.dims && a.index_to_world == b.index_to_world && a.voxels == b.voxels)
      edited.volumes[i].data = base.volumes[i].data;
  }
  for (size_t i = 0; i < edited.meshes.size() && i < base.meshes.size(); ++i) {
    const Mesh &a = *edited.meshes[i].mesh, &b = *base.meshes[i].mesh;
    if (a.positions == b.positions && a.normals == b.normals && a.triangles == b.triangles)
      edited.meshes[i].mesh = base.meshes[i].mesh;
  }
}

}  // namespace

ChangeTiming time_change(const Scene& base, const std::string& scene_file,
                         std::vector<std::string> overrides, const std::string& change,
                         const RenderOptions& options, int frames) {
  overrides.push_back("objects." + change);
  Scene edited = load_scene(scene_file, overrides);
  share_unchanged_data(edited, base);
  Renderer renderer;
  ChangeTiming t;
  renderer.render(edited, options);  // warm-up
  auto ms_since = [](std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
  };
  for (int f = 0; f < frames; ++f) {
    renderer.render(base, options);
    auto start = std::chrono::steady_clock::now();
    renderer.render(edited, options);
    t.ms.push_back(ms_since(start));
    const RendererStats& s = renderer.last_stats();
    t.stages = s.stages;
    t.stages_run = s.stages_run;
    t.stages_merged = s.stages_merged;
    t.kept_bytes_per_pixel = s.kept_bytes_per_pixel;
    start = std::chrono::steady_clock::now();
    imx::render(edited, options);
    t.fresh_ms.push_back(ms_since(start));
  }
  return t;
}

}  // namespace imx::cli
