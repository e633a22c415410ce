#include "probes/first_hit_depth.hpp"

#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "core/parallel.hpp"
#include "frame/clip_intervals.hpp"
#include "frame/frame_setup.hpp"
#include "intermix/error.hpp"
#include "raster/rasterizer.hpp"
#include "slab/over.hpp"
#include "volume/iso_crossing.hpp"
#include "volume/projection.hpp"
#include "volume/volume_marcher.hpp"

namespace imx {

Image first_hit_depth(const Scene& scene, const std::string& name, float opacity, int threads) {
  Scene one = scene;  // the object alone
  one.meshes.clear();
  one.planes.clear();
  one.streamlines.clear();
  one.order.clear();
  for (VolumeObject& v : one.volumes) v.clip_meshes.clear();  // a cutter alone is drawn too
  int volume = -1;
  for (const ObjectRef& ref : scene.order) {
    if (ref.kind == ObjectKind::volume && scene.volumes[ref.index].name == name) volume = ref.index;
    if (ref.kind == ObjectKind::mesh && scene.meshes[ref.index].name == name) {
      one.order.push_back({ObjectKind::mesh, 0});
      one.meshes.push_back(scene.meshes[ref.index]);
    }
    if (ref.kind == ObjectKind::plane && scene.planes[ref.index].name == name) {
      one.order.push_back({ObjectKind::plane, 0});
      one.planes.push_back(scene.planes[ref.index]);
    }
    if (ref.kind == ObjectKind::streamlines && scene.streamlines[ref.index].name == name) {
      one.order.push_back({ObjectKind::streamlines, 0});
      one.streamlines.push_back(scene.streamlines[ref.index]);
      one.streamlines.back().clip_meshes.clear();  // they name the scene's meshes
    }
  }
  if (volume < 0 && one.order.empty())
    throw Error(fmt::format("first-hit depth: the scene has no object named '{}'", name));

  FrameSetup frame(scene);
  const int w = scene.image.width, h = scene.image.height;
  const float inf = std::numeric_limits<float>::infinity();
  Image depth(w, h, glm::vec4(inf, 0.0f, 0.0f, 1.0f));
  const glm::vec2 centre(0.5f);
  if (volume < 0) {
    Rasterizer raster(one, frame.camera, frame.volumes, 16);
    for_each_tile(w, h, 16, threads, [&](const TileRect& tile, int) {
      SampleFragments f;
      raster.rasterize(tile, std::span<const glm::vec2>(&centre, 1), f);
      size_t s = 0;
      for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x, ++s)
          if (!f.of(s).empty()) depth.at(x, y).r = f.of(s).front().t;
    });
    return depth;
  }
  PreparedVolume& v = frame.volumes[volume];
  const float step = v.min_pitch;
  if (v.object->style == VolumeStyle::dvr)
    v.accel = accelerate(*v.object, v.lut, step, MarchSettings::from(scene.render));
  // A clipped volume keeps what its clip meshes leave of each ray.
  std::optional<Rasterizer> clip_raster;
  if (frame.clip.clips(static_cast<size_t>(volume)))
    clip_raster.emplace(scene, frame.camera, frame.volumes, 16, RasterObjects::clip);
  for_each_tile(w, h, 16, threads, [&](const TileRect& tile, int) {
    SampleFragments clip;
    if (clip_raster) clip_raster->rasterize(tile, std::span<const glm::vec2>(&centre, 1), clip);
    size_t s = 0;
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x, ++s) {
        Ray ray = frame.camera.ray(x + 0.5, y + 0.5);
        RayInterval span = v.intersect(ray);
        if (span.empty()) continue;
        ClipPieces pieces;
        KeptSpan kept(span);
        if (clip_raster) {
          clip_volume(clip.of(s), frame.clip.view(), static_cast<size_t>(volume), pieces);
          kept = KeptSpan(span, pieces);
        }
        if (kept.empty()) continue;
        if (v.object->style == VolumeStyle::dvr) {
          VolumeMarcher marcher(v, ray, kept, step, frame.lights);
          glm::vec4 acc(0.0f);
          Slab s;
          while (marcher.next(s)) {
            float before = acc.a;
            acc = over(acc, s.color);
            if (acc.a >= opacity) {  // where inside the slab, linearly
              float f = (opacity - before) / std::max(acc.a - before, 1e-9f);
              depth.at(x, y).r = s.front() + f * s.thickness;
              break;
            }
          }
        } else {
          VolumeHit hit;
          bool found = v.object->style == VolumeStyle::iso
                           ? find_iso_crossing(v, ray, kept, step, 10, frame.lights, hit)
                           : project_volume(v, ray, kept, step, hit);
          if (found) depth.at(x, y).r = static_cast<float>(hit.t);
        }
      }
  });
  return depth;
}

}  // namespace imx
