#include "methods/zslab.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "core/colour.hpp"
#include "core/parallel.hpp"
#include "intermix/limits.hpp"
#include "methods/stage_hash.hpp"
#include "methods/zslab_buffer.hpp"
#include "methods/zslab_frame.hpp"

namespace imx {

namespace {

constexpr int kTileSize = 16;

// Index of the first stage that is not stored (the on-the-fly one), or stages.size().
size_t deferred_end(const ZslabFrame& z) {
  size_t k = 0;
  while (k < z.stages.size() && !z.stages[k].on_the_fly) ++k;
  return k;
}

// Calls fn(x, y, ray, sample index in the tile) for every sample of the tile, row by row.
template <class Fn>
void for_each_sample(const ZslabFrame& z, const TileRect& tile, const Fn& fn) {
  size_t i = 0;
  for (int y = tile.y0; y < tile.y1; ++y)
    for (int x = tile.x0; x < tile.x1; ++x)
      for (const glm::vec2& o : z.offsets) {
        fn(x, y, z.frame.camera.ray(x + o.x, y + o.y), i);
        ++i;
      }
}

void report(const RenderOptions& options, int done, int total) {
  if (options.progress) options.progress(static_cast<double>(done) / total);
}

// Whether stage k (the on-the-fly one when k is past the deferred stages) casts a clipped volume.
bool clipped_stage(const ZslabFrame& z, size_t k) {
  return k < z.stages.size() && z.stages[k].kind == ZslabStage::Kind::volume &&
         z.frame.clip.clips(z.stages[k].volume);
}

// Sample i's clip-mesh fragments, when `clip` holds the tile's.
std::span<const Fragment> clip_row(const SampleFragments& clip, bool have, size_t i) {
  return have ? clip.of(i) : std::span<const Fragment>();
}

// Stateless pipeline: every stage runs on one tile's ping-pong ZT-buffers before the next tile;
// a flag bit per sample says which of the two holds its array (untouched samples cost nothing).
Image render_streamed(const Scene& scene, int spp, const RenderOptions& options, bool hybrid) {
  ZslabFrame z(scene, spp, hybrid);
  z.prepare();
  const size_t end = deferred_end(z);
  const int n = z.params.layers;
  const int w = scene.image.width, h = scene.image.height;
  Image image(w, h);
  const float weight = 1.0f / static_cast<float>(z.offsets.size());
  for_each_tile(
      w, h, kTileSize, options.threads,
      [&](const TileRect& tile, int) {
        const size_t samples = static_cast<size_t>(tile.width()) * tile.height() * z.offsets.size();
        ZtBuffer zt[2] = {ZtBuffer(samples, n, z.format), ZtBuffer(samples, n, z.format)};
        std::vector<uint32_t> flags((samples + 31) / 32, 0u);
        auto current = [&](size_t i) { return (flags[i / 32] >> (i % 32)) & 1u; };
        SampleFragments fragments, clip;
        const bool have_clip = z.rasterize_clip(tile, clip);
        Slab in_slots[kMaxZslabLayers], out_slots[kMaxZslabLayers];
        for (size_t k = 0; k < end; ++k) {
          const bool surfaces = z.stages[k].kind == ZslabStage::Kind::surfaces;
          if (surfaces) z.rasterize(k, tile, fragments);
          for_each_sample(z, tile, [&](int x, int y, const Ray& ray, size_t i) {
            std::span<const Fragment> f = surfaces ? fragments.of(i) : std::span<const Fragment>();
            if (surfaces && f.empty()) return;
            uint32_t c = current(i);
            int count = zt[c].load(i, in_slots);
            SlabList out(std::span<Slab>(out_slots, static_cast<size_t>(n)));
            if (!z.run_deferred(k, x, y, ray, f, std::span<const Slab>(in_slots, count), out,
                                clip_row(clip, have_clip, i)))
              return;
            zt[1 - c].store(i, out.items());
            flags[i / 32] ^= 1u << (i % 32);
          });
        }
        glm::vec4 sum(0.0f);
        size_t done = 0;
        for_each_sample(z, tile, [&](int x, int y, const Ray& ray, size_t i) {
          int count = zt[current(i)].load(i, in_slots);
          sum += z.run_final(end, x, y, ray, std::span<const Slab>(in_slots, count),
                             clip_row(clip, have_clip, i));
          if (++done == z.offsets.size()) {
            image.at(x, y) = over_background(sum * weight, scene.image.background);
            sum = glm::vec4(0.0f);
            done = 0;
          }
        });
      },
      [&](int done, int total) { report(options, done, total); });
  return image;
}

}  // namespace

Image render_zslab(const Scene& scene, int spp, const RenderOptions& options) {
  return render_streamed(scene, spp, options, false);
}

Image render_zslab_hybrid(const Scene& scene, int spp, const RenderOptions& options) {
  return render_streamed(scene, spp, options, true);
}

double zslab_stream_bytes_per_sample(const RenderSettings& r) {
  int size = slab_bytes(r.slab_format == "rgba8" ? SlabFormat::rgba8 : SlabFormat::rgba32f);
  return static_cast<double>((2 * r.layers + r.rt_layers) * size) + 1.0 / 8.0;
}

Image render_zslab_cached(const Scene& scene, int spp, const RenderOptions& options, bool hybrid,
                          ZslabStageCache& cache, ZslabStats* stats) {
  ZslabFrame z(scene, spp, hybrid);
  const size_t end = deferred_end(z);
  const int n = z.params.layers;
  const int w = scene.image.width, h = scene.image.height;
  const size_t spx = z.offsets.size();
  const size_t total = static_cast<size_t>(w) * h * spx;
  check_memory(static_cast<uint64_t>(static_cast<double>(total) *
                                     zslab_stream_bytes_per_sample(scene.render)),
               fmt::format("zslab's kept stage outputs for {}x{} pixels at {} spp", w, h, spx));

  // Stage k's key chains the keys of all stages before it.
  std::vector<uint64_t> keys(z.stages.size());
  uint64_t prev = z.frame_key();
  for (size_t k = 0; k < z.stages.size(); ++k)
    prev = keys[k] = StageHash().add(prev).add(z.stages[k].content).value();
  const uint64_t image_key = StageHash()
                                 .add(z.stages.empty() ? z.frame_key() : keys.back())
                                 .add(scene.image.background)
                                 .value();
  if (cache.stages.size() != z.stages.size()) cache.stages.assign(z.stages.size(), {});

  ZslabStats st;
  st.stages = static_cast<int>(z.stages.size());
  st.stream_bytes_per_pixel = zslab_stream_bytes_per_sample(scene.render) * spx;
  if (cache.image && cache.image_key == image_key) {
    for (const auto& e : cache.stages)
      if (e.output) st.kept_bytes_per_pixel += static_cast<double>(e.output->bytes()) / (w * h);
    if (stats) *stats = st;
    return *cache.image;
  }

  // Resume after the last deferred stage whose kept output is still valid.
  size_t first = 0;
  for (size_t k = end; k-- > 0;)
    if (cache.stages[k].output && cache.stages[k].key == keys[k]) {
      first = k + 1;
      break;
    }
  std::shared_ptr<const ZtBuffer> input = first > 0 ? cache.stages[first - 1].output : nullptr;
  z.prepare(first);

  // Kept outputs are limited to what the ping-pong pair and the RT layers would hold, (2N + M)
  // slabs per sample, given to the stages nearest the end (the inputs of the likeliest edits).
  const size_t keep =
      static_cast<size_t>(std::max(1, (2 * n + z.params.rt_layers) / std::max(n, 1)));
  for (size_t k = 0; k < cache.stages.size(); ++k)
    if (k + keep < end || k >= end || cache.stages[k].key != keys[k]) cache.stages[k] = {};

  for (size_t k = first; k < end; ++k) {
    auto output = std::make_shared<ZtBuffer>(total, n, z.format);
    const bool surfaces = z.stages[k].kind == ZslabStage::Kind::surfaces;
    const bool clipped = clipped_stage(z, k);
    for_each_tile(w, h, kTileSize, options.threads, [&](const TileRect& tile, int) {
      SampleFragments fragments, clip;
      if (surfaces) z.rasterize(k, tile, fragments);
      const bool have_clip = clipped && z.rasterize_clip(tile, clip);
      Slab in_slots[kMaxZslabLayers], out_slots[kMaxZslabLayers];
      for_each_sample(z, tile, [&](int x, int y, const Ray& ray, size_t i) {
        size_t g = (static_cast<size_t>(y) * w + x) * spx + i % spx;
        std::span<const Fragment> f = surfaces ? fragments.of(i) : std::span<const Fragment>();
        if (surfaces && f.empty()) {
          if (input) output->copy(g, *input, g);
          return;
        }
        int count = input ? input->load(g, in_slots) : 0;
        SlabList out(std::span<Slab>(out_slots, static_cast<size_t>(n)));
        if (z.run_deferred(k, x, y, ray, f, std::span<const Slab>(in_slots, count), out,
                           clip_row(clip, have_clip, i)))
          output->store(g, out.items());
        else if (input)
          output->copy(g, *input, g);
      });
    });
    ++st.stages_run;
    input = output;
    ZslabStageCache::Entry& e = cache.stages[k];
    e = {};
    if (k + keep >= end) {
      e.key = keys[k];
      e.output = output;
      for (uint32_t o : z.stages[k].objects) {
        const ObjectRef& ref = scene.order[o];
        if (ref.kind == ObjectKind::volume) {
          e.keep_alive.push_back(scene.volumes[ref.index].data);
          for (const ClipMesh& c : scene.volumes[ref.index].clip_meshes)
            e.keep_alive.push_back(scene.meshes[c.mesh].mesh);
        }
        if (ref.kind == ObjectKind::mesh) e.keep_alive.push_back(scene.meshes[ref.index].mesh);
        if (ref.kind == ObjectKind::plane && scene.planes[ref.index].volume >= 0)
          e.keep_alive.push_back(scene.volumes[scene.planes[ref.index].volume].data);
      }
    }
  }

  auto image = std::make_shared<Image>(w, h);
  const float weight = 1.0f / static_cast<float>(spx);
  const bool clipped_final = clipped_stage(z, end);
  for_each_tile(
      w, h, kTileSize, options.threads,
      [&](const TileRect& tile, int) {
        Slab slots[kMaxZslabLayers];
        SampleFragments clip;
        const bool have_clip = clipped_final && z.rasterize_clip(tile, clip);
        glm::vec4 sum(0.0f);
        for_each_sample(z, tile, [&](int x, int y, const Ray& ray, size_t i) {
          size_t g = (static_cast<size_t>(y) * w + x) * spx + i % spx;
          int count = input ? input->load(g, slots) : 0;
          sum += z.run_final(end, x, y, ray, std::span<const Slab>(slots, count),
                             clip_row(clip, have_clip, i));
          if (i % spx + 1 == spx) {
            image->at(x, y) = over_background(sum * weight, scene.image.background);
            sum = glm::vec4(0.0f);
          }
        });
      },
      [&](int done, int all) { report(options, done, all); });
  if (end < z.stages.size()) ++st.stages_run;
  cache.image = image;
  cache.image_key = image_key;
  for (const auto& e : cache.stages)
    if (e.output) st.kept_bytes_per_pixel += static_cast<double>(e.output->bytes()) / (w * h);
  if (stats) *stats = st;
  return *image;
}

}  // namespace imx
