// csg_ray_statistics: a 1-spp pass that classifies every ray as render_csg does and counts.
#include "probes/csg_statistics.hpp"

#include <algorithm>
#include <vector>

#include "core/parallel.hpp"
#include "frame/csg_frame.hpp"
#include "frame/frame_setup.hpp"
#include "frame/sample_pattern.hpp"
#include "intermix/error.hpp"
#include "methods/csg/csg_kernel.hpp"
#include "methods/mdvr/mdvr.hpp"
#include "raster/rasterizer.hpp"

namespace imx {
namespace {

// Whether the ray meets a CSG primitive at all: a fragment of a CSG mesh or a CSG volume span.
bool meets_csg(std::span<const Fragment> row, const RayVolumes& rv, const CsgView& csg) {
  for (int v = 0; v < rv.count; ++v)
    if (csg.primitive_of_volume[v] >= 0 && rv.span[v].t1 > rv.span[v].t0) return true;
  return std::any_of(row.begin(), row.end(), [&](const Fragment& f) {
    return f.object < csg.primitive_of_object.size() && csg.primitive_of_object[f.object] >= 0;
  });
}

void add(CsgRayStatistics& sum, const CsgRayStatistics& part) {
  sum.rays += part.rays;
  sum.meeting += part.meeting;
  sum.intervals += part.intervals;
  sum.max_intervals = std::max(sum.max_intervals, part.max_intervals);
  sum.ranges += part.ranges;
  sum.max_ranges = std::max(sum.max_ranges, part.max_ranges);
  sum.tested += part.tested;
  sum.inconsistent += part.inconsistent;
  sum.inconsistent_examples.insert(sum.inconsistent_examples.end(),
                                   part.inconsistent_examples.begin(),
                                   part.inconsistent_examples.end());
}

}  // namespace

CsgRayStatistics csg_ray_statistics(const Scene& scene, int threads) {
  if (!scene.csg) throw Error("csg: the scene has no csg block");
  // The frame exactly as render_csg prepares it, so the classification is the method's own.
  FrameSetup frame(scene);
  frame.require_per_sample_support("csg");
  const MdvrParams params = prepare_mdvr(scene, frame, false);
  const CsgFrame csg_frame(scene, frame, /*with_states=*/true);
  const CsgView csg = csg_frame.view();

  constexpr int kTileSize = 16;
  const std::vector<glm::vec2> offsets = stratified_offsets(1);
  const glm::vec2 o = offsets.front();
  const Rasterizer raster(scene, frame.camera, frame.volumes, kTileSize);
  const int w = scene.image.width, h = scene.image.height;
  const int tiles = ((w + kTileSize - 1) / kTileSize) * ((h + kTileSize - 1) / kTileSize);
  // One result per tile, summed in tile order afterwards: no shared state between threads.
  std::vector<CsgRayStatistics> per_tile(tiles);
  for_each_tile(w, h, kTileSize, threads, [&](const TileRect& tile, int index) {
    CsgRayStatistics& s = per_tile[index];
    SampleFragments fragments;
    raster.rasterize(tile, offsets, fragments, FragmentOrder::depth);
    std::vector<Fragment> surfaces;
    std::vector<CsgRange> ranges;
    size_t sample = 0;
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) {
        const std::span<const Fragment> row = fragments.of(sample++);
        if (surfaces.size() < row.size()) surfaces.resize(row.size());
        if (ranges.size() < csg_range_capacity(row.size()))
          ranges.resize(csg_range_capacity(row.size()));
        const Ray ray = frame.camera.ray(x + o.x, y + o.y);
        const RayVolumes rv(ray, frame.volumes, params.step, params.iso_bisections, frame.lights,
                            frame.volumes_may_show(x, y));
        const CsgIntervals iv =
            classify_csg_sample(ray, row, frame.volumes, rv, csg, surfaces, ranges);
        ++s.rays;
        if (iv.inconsistent) {
          ++s.inconsistent;
          if (s.inconsistent_examples.size() < size_t(CsgRayStatistics::kMaxExamples))
            s.inconsistent_examples.push_back({x, y});
        }
        if (!meets_csg(row, rv, csg)) continue;
        ++s.meeting;
        s.intervals += iv.intervals;
        s.max_intervals = std::max(s.max_intervals, iv.intervals);
        s.ranges += iv.range_count;
        s.max_ranges = std::max(s.max_ranges, iv.range_count);
        if (std::any_of(ranges.begin(), ranges.begin() + iv.range_count,
                        [](const CsgRange& r) { return r.needs_test; }))
          ++s.tested;
      }
  });

  CsgRayStatistics total;
  total.width = w;
  total.height = h;
  for (const CsgRayStatistics& part : per_tile) add(total, part);
  // Each tile kept its first examples in row-major order, so the image's first ones are among
  // them.
  std::sort(total.inconsistent_examples.begin(), total.inconsistent_examples.end(),
            [](CsgPixel a, CsgPixel b) { return a.y != b.y ? a.y < b.y : a.x < b.x; });
  if (total.inconsistent_examples.size() > size_t(CsgRayStatistics::kMaxExamples))
    total.inconsistent_examples.resize(CsgRayStatistics::kMaxExamples);
  return total;
}

}  // namespace imx
