#include "methods/mdvr/mdvr.hpp"

#include <algorithm>
#include <cmath>

#include "core/colour.hpp"
#include "core/parallel.hpp"
#include "frame/frame_setup.hpp"
#include "frame/ray_base.hpp"
#include "frame/sample_pattern.hpp"
#include "methods/mdvr/mdvr_kernel.hpp"
#include "raster/rasterizer.hpp"
#include "volume/packet_marcher.hpp"
#include "volume/packet_projection.hpp"

namespace imx {

namespace {

// One volume and nothing else shown: the scene part of volume_packets_apply.
bool one_volume_alone(const Scene& scene, const FrameSetup& frame) {
  // Hidden meshes, planes and tubes make no fragments (a viewer's reading planes, hidden in 3-D).
  const std::vector<bool> meshes = shown_meshes(scene);
  return scene.render.packets && std::find(meshes.begin(), meshes.end(), true) == meshes.end() &&
         std::none_of(scene.planes.begin(), scene.planes.end(), shown_plane) &&
         std::none_of(scene.streamlines.begin(), scene.streamlines.end(),
                      [](const StreamlineObject& o) { return o.opacity > 0.0f; }) &&
         frame.clip.empty() && frame.volumes.size() == 1;
}

}  // namespace

bool volume_packets_apply(const Scene& scene, const FrameSetup& frame) {
  if (!one_volume_alone(scene, frame)) return false;
  const PreparedVolume& v = frame.volumes[0];
  return v.object->style == VolumeStyle::dvr ? packet_marching_supported(v, frame.lights)
                                             : packet_projection_supported(v);
}

void accelerate_for_packets(const Scene& scene, FrameSetup& frame, std::span<const float> steps,
                            bool packets_possible) {
  const MarchSettings settings = MarchSettings::from(scene.render);
  if (packets_possible && settings.gradients == GradientSource::automatic &&
      one_volume_alone(scene, frame)) {
    MarchSettings on_the_fly = settings;
    on_the_fly.gradients = GradientSource::on_the_fly;
    frame.accelerate(steps, on_the_fly);
    if (volume_packets_apply(scene, frame)) return;
  }
  frame.accelerate(steps, settings);
}

Image render_volume_packets(const Scene& scene, const FrameSetup& frame, const MdvrParams& params,
                            SlabExtent extent, const RenderOptions& options,
                            std::span<const glm::vec2> offsets) {
  constexpr int kTileSize = 16;
  const PreparedVolume& v = frame.volumes[0];
  const bool visible = v.lut.max_opacity() > 0.0f;  // else RayVolumes marches nothing
  const int w = scene.image.width, h = scene.image.height;
  Image image(w, h);
  const glm::vec4 background = scene.image.background;
  const float weight = 1.0f / static_cast<float>(offsets.size());
  const PacketCamera camera(frame.camera);
  for_each_tile(
      w, h, kTileSize, options.threads,
      [&](const TileRect& tile, int) {
        PacketRay rays[kTileSize * kTileSize];
        int pixel[kTileSize * kTileSize];  // the ray's pixel in the tile, row by row
        glm::vec4 colour[kTileSize * kTileSize];
        glm::vec4 sum[kTileSize * kTileSize] = {};
        const int tw = tile.width();
        // Each sample position in turn, every pixel's samples summed in pattern order as
        // render_per_sample sums them.
        for (const glm::vec2& o : offsets) {
          int n = 0;
          // In blocks of 4 x 2 pixels, so that the eight rays of a packet stay close together
          // (ct-head 36.0 against 37.5 ms in rows of 8). Pixels no occupied brick reaches cast
          // no ray: they would find nothing (40-55% of the rays that meet the box, ct-head and
          // FLAIR).
          auto add = [&](int x, int y) {
            if (!visible || !frame.may_show(0, x, y)) return;
            rays[n] = {frame.camera.ray(x + o.x, y + o.y)};
            pixel[n++] = (y - tile.y0) * tw + (x - tile.x0);
          };
          for (int y = tile.y0; y < tile.y1; y += 2) {
            for (int x = tile.x0; x < tile.x1; x += 4) {
              const bool whole = x + 4 <= tile.x1 && y + 2 <= tile.y1;
              if (whole && visible && frame.may_show(0, x, y)) {
                camera.block(x, y, rays + n, o);
                for (int k = 0; k < 8; ++k)
                  pixel[n++] = (y + k / 4 - tile.y0) * tw + (x + k % 4 - tile.x0);
                continue;
              }
              for (int dy = 0; dy < 2 && y + dy < tile.y1; ++dy)
                for (int dx = 0; dx < 4 && x + dx < tile.x1; ++dx) add(x + dx, y + dy);
            }
          }
          // The box test in lanes, then only the rays that meet the volume, in the same order.
          intersect_packets(v, std::span<PacketRay>(rays, n));
          int kept = 0;
          for (int k = 0; k < n; ++k)
            if (!RayInterval{rays[k].t0, rays[k].t1}.empty())
              rays[kept] = rays[k], pixel[kept++] = pixel[k];
          n = kept;
          if (v.object->style == VolumeStyle::dvr)
            composite_packets(v, std::span<const PacketRay>(rays, n), params.step, frame.lights,
                              params.ert, std::span<glm::vec4>(colour, n), extent);
          else
            project_packets(v, std::span<const PacketRay>(rays, n), params.step,
                            params.iso_bisections, frame.lights, std::span<glm::vec4>(colour, n));
          for (int k = 0; k < n; ++k) sum[pixel[k]] += colour[k];
        }
        for (int y = tile.y0; y < tile.y1; ++y)
          for (int x = tile.x0; x < tile.x1; ++x)
            image.at(x, y) =
                over_background(sum[(y - tile.y0) * tw + (x - tile.x0)] * weight, background);
      },
      [&](int done, int total) {
        if (options.progress) options.progress(static_cast<double>(done) / total);
      });
  return image;
}

MdvrParams prepare_mdvr(const Scene& scene, FrameSetup& frame, bool packets_possible) {
  MdvrParams params;
  params.step = static_cast<float>(frame.ray_step(scene.render));
  params.ert = static_cast<float>(scene.render.ert_threshold);
  const std::vector<float> steps(frame.volumes.size(), params.step);
  accelerate_for_packets(scene, frame, steps, packets_possible);
  return params;
}

Image render_mdvr(const Scene& scene, int spp, const RenderOptions& options) {
  FrameSetup frame(scene);
  frame.require_per_sample_support("mdvr");
  const MdvrParams params = prepare_mdvr(scene, frame, true);
  if (volume_packets_apply(scene, frame))
    return render_volume_packets(scene, frame, params, SlabExtent::grid, options,
                                 frame_offsets(spp, options.sample_index));
  return render_per_sample(
      scene, frame, spp, options,
      [&](const Ray& ray, std::span<const Fragment> fragments, const VolumeFilter& filter) {
        return trace_mdvr(ray, fragments, frame.volumes, frame.lights, params, filter);
      });
}

}  // namespace imx
