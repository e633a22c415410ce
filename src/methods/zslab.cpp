#include "methods/zslab.hpp"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "core/colour.hpp"
#include "core/parallel.hpp"
#include "intermix/limits.hpp"
#include "methods/stage_hash.hpp"
#include "methods/zslab_frame.hpp"
#include "methods/zslab_kept.hpp"
#include "methods/zslab_object_kernel.hpp"
#include "slab/zt_buffer.hpp"

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
// With `arrays`, every stage is deferred and each sample's array is stored there instead of
// composited (the image is then left empty).
Image render_streamed(const Scene& scene, int spp, const RenderOptions& options, bool hybrid,
                      ZtBuffer* arrays = nullptr) {
  ZslabFrame z(scene, spp, hybrid, options.sample_index);
  z.prepare();
  const size_t end = deferred_end(z);
  const int n = z.params.layers;
  const int w = scene.image.width, h = scene.image.height;
  Image image(w, h);
  const float weight = 1.0f / static_cast<float>(z.offsets.size());
  if (arrays) arrays->reset(static_cast<size_t>(w) * h * z.offsets.size(), n, z.format);
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
        if (arrays) {
          const size_t per_pixel = z.offsets.size();
          for_each_sample(z, tile, [&](int x, int y, const Ray&, size_t i) {
            size_t pixel = static_cast<size_t>(y) * w + x;
            arrays->copy(pixel * per_pixel + i % per_pixel, zt[current(i)], i);
          });
          return;
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

void render_zslab_arrays(const Scene& scene, int spp, const RenderOptions& options,
                         ZtBuffer& arrays) {
  render_streamed(scene, spp, options, false, &arrays);
}

double zslab_stream_bytes_per_sample(const RenderSettings& r) {
  int size = slab_bytes(r.slab_format == "rgba8" ? SlabFormat::rgba8 : SlabFormat::rgba32f);
  return static_cast<double>((2 * r.layers + r.rt_layers) * size) + 1.0 / 8.0;
}

size_t ZslabStageCache::kept_bytes() const {
  size_t bytes = prefix.slabs ? prefix.slabs->bytes() : 0;
  for (const Kept& e : own)
    if (e.slabs) bytes += e.slabs->bytes();
  return bytes;
}

namespace {

// The data stage k's key hashed by identity, kept alive as long as the key is.
void keep_alive_of(const Scene& scene, const ZslabStage& stage,
                   std::vector<std::shared_ptr<const void>>& out) {
  for (uint32_t o : stage.objects) {
    const ObjectRef& ref = scene.order[o];
    if (ref.kind == ObjectKind::volume) {
      out.push_back(scene.volumes[ref.index].data);
      for (const ClipMesh& c : scene.volumes[ref.index].clip_meshes)
        out.push_back(scene.meshes[c.mesh].mesh);
    }
    if (ref.kind == ObjectKind::mesh) out.push_back(scene.meshes[ref.index].mesh);
    if (ref.kind == ObjectKind::plane && scene.planes[ref.index].volume >= 0)
      out.push_back(scene.volumes[scene.planes[ref.index].volume].data);
  }
}

// What a ZT-buffer store and load do to a stage's output (thickness clamped, RGBA8 rounding), so
// merging on the stack gives the bytes of the ping-pong pipeline. Returns the kept length.
int as_stored(std::span<Slab> slabs, SlabFormat format) {
  for (size_t k = 0; k < slabs.size(); ++k) {
    Slab& s = slabs[k];
    s.thickness = std::max(s.thickness, 0.0f);
    if (format == SlabFormat::rgba8) s = unpack(pack8(s));
    if (!(s.thickness >= 0.0f)) return static_cast<int>(k);
  }
  return static_cast<int>(slabs.size());
}

// An array of `samples` x `capacity`: one that `pool` holds in that shape, else a new one.
std::shared_ptr<KeptSlabArrays> take(std::vector<std::shared_ptr<KeptSlabArrays>>& pool,
                                     size_t samples, int capacity) {
  for (auto& p : pool)
    if (p && p->samples() == samples && p->capacity() == std::max(capacity, 1))
      return std::exchange(p, nullptr);
  return std::make_shared<KeptSlabArrays>(samples, capacity);
}

}  // namespace

Image render_zslab_cached(const Scene& scene, int spp, const RenderOptions& options, bool hybrid,
                          ZslabStageCache& cache, ZslabStats* stats) {
  ZslabFrame z(scene, spp, hybrid, options.sample_index);
  const size_t end = deferred_end(z);
  const int n = z.params.layers;
  const int w = scene.image.width, h = scene.image.height;
  const size_t spx = z.offsets.size();
  const size_t total = static_cast<size_t>(w) * h * spx;

  // Own keys hash the frame and the stage's own content only; the prefix key chains the stages
  // before it, the image key all of them.
  std::vector<uint64_t> own_key(z.stages.size()), chain(z.stages.size() + 1);
  std::vector<int> capacity(end);
  chain[0] = z.frame_key();
  for (size_t k = 0; k < z.stages.size(); ++k) {
    own_key[k] = StageHash().add(z.frame_key()).add(z.stages[k].content).value();
    chain[k + 1] = StageHash().add(chain[k]).add(z.stages[k].content).value();
    if (k < end) capacity[k] = z.own_capacity(k);
  }
  const uint64_t image_key = StageHash().add(chain.back()).add(scene.image.background).value();

  ZslabStats st;
  st.stages = static_cast<int>(z.stages.size());
  st.stream_bytes_per_pixel = zslab_stream_bytes_per_sample(scene.render) * spx;
  auto finish_stats = [&]() {
    st.kept_bytes_per_pixel =
        static_cast<double>(cache.kept_bytes()) / (static_cast<double>(w) * h);
    if (stats) *stats = st;
  };
  if (cache.image && cache.image_key == image_key) {
    finish_stats();
    return *cache.image;
  }

  // The budget: own arrays by size, the largest evicted first (ties: the later stage), then the
  // merged prefix in what they leave. An evicted own array is recomputed each frame.
  std::vector<bool> keep(end, false);
  std::vector<size_t> by_size;
  uint64_t planned = 0;
  for (size_t k = 0; k < end; ++k)
    if (capacity[k] > 0) {
      keep[k] = true;
      by_size.push_back(k);
      planned += KeptSlabArrays::bytes_for(total, capacity[k]);
    }
  std::stable_sort(by_size.begin(), by_size.end(), [&](size_t a, size_t b) {
    return capacity[a] != capacity[b] ? capacity[a] > capacity[b] : a > b;
  });
  for (size_t k : by_size) {
    if (planned <= cache.budget_bytes) break;
    keep[k] = false;
    planned -= KeptSlabArrays::bytes_for(total, capacity[k]);
  }

  // Match the kept own arrays; the rest become storage for this frame's recomputed ones.
  std::vector<std::shared_ptr<KeptSlabArrays>> pool, matched(end), writing(end);
  std::vector<ZslabStageCache::Kept> old = std::move(cache.own);
  cache.own.clear();
  for (size_t k = 0; k < end; ++k) {
    if (!keep[k]) continue;
    for (auto& e : old)
      if (e.slabs && e.key == own_key[k] && e.slabs->samples() == total &&
          e.slabs->capacity() == capacity[k]) {
        matched[k] = e.slabs;
        cache.own.push_back(std::move(e));
        break;
      }
  }
  for (auto& e : old)
    if (e.slabs) pool.push_back(std::move(e.slabs));

  // The first stage whose object must be rendered, and where the merges start.
  size_t first = end;
  for (size_t k = 0; k < end && first == end; ++k)
    if (!matched[k]) first = k;
  const size_t prefix_at = cache.prefix_stage;
  const bool prefix_valid = cache.prefix.slabs && prefix_at >= 1 && prefix_at <= first &&
                            cache.prefix.key == chain[prefix_at] &&
                            cache.prefix.slabs->samples() == total &&
                            cache.prefix.slabs->capacity() == n;
  const size_t start = prefix_valid ? prefix_at : 0;
  // Keep the merged array before the first changed stage, the input of the likeliest next edit,
  // when it saves two merges or more (or all of them), within the budget.
  const uint64_t prefix_bytes = KeptSlabArrays::bytes_for(total, n);
  const bool write_prefix =
      first > start && (first >= 2 || first == end) && planned + prefix_bytes <= cache.budget_bytes;
  std::shared_ptr<KeptSlabArrays> prefix = prefix_valid ? cache.prefix.slabs : nullptr;
  if (!prefix_valid) cache.prefix = {};
  if (write_prefix) {
    if (!prefix) prefix = take(pool, total, n);  // written in place: each sample reads, then writes
  } else if (!prefix_valid) {
    prefix = nullptr;
  } else if (planned + prefix_bytes > cache.budget_bytes) {
    cache.prefix = {};  // still read this frame, then dropped
  }

  std::vector<bool> render_stage(end, false);
  size_t prepare_from = end;
  bool clip_needed = clipped_stage(z, end);
  for (size_t k = start; k < end; ++k) {
    if (matched[k]) continue;
    render_stage[k] = true;
    prepare_from = std::min(prepare_from, k);
    clip_needed = clip_needed || clipped_stage(z, k);
    if (keep[k]) writing[k] = take(pool, total, capacity[k]);
    ++st.stages_run;
  }
  pool.clear();
  st.stages_merged = static_cast<int>(end - start);
  check_memory(planned + (write_prefix || prefix ? prefix_bytes : 0),
               fmt::format("zslab's kept slab arrays for {}x{} pixels at {} spp", w, h, spx));
  z.prepare(prepare_from);

  auto image = std::make_shared<Image>(w, h);
  const float weight = 1.0f / static_cast<float>(spx);
  for_each_tile(
      w, h, kTileSize, options.threads,
      [&](const TileRect& tile, int) {
        std::vector<SampleFragments> fragments(end);
        for (size_t k = start; k < end; ++k)
          if (render_stage[k] && z.stages[k].kind == ZslabStage::Kind::surfaces)
            z.rasterize(k, tile, fragments[k]);
        SampleFragments clip;
        const bool have_clip = clip_needed && z.rasterize_clip(tile, clip);
        Slab run[2][kMaxZslabLayers];
        Slab own[std::max(kMaxOwnSurfaceSlabs, kMaxZslabLayers)];
        // First each object to render, stage by stage over the tile (one volume's bricks stay
        // in cache), into its kept array or, when evicted, a tile-local one.
        std::vector<std::unique_ptr<KeptSlabArrays>> local(end);
        const size_t tile_samples =
            static_cast<size_t>(tile.width()) * static_cast<size_t>(tile.height()) * spx;
        for (size_t k = start; k < end; ++k) {
          if (!render_stage[k] || capacity[k] == 0) continue;
          if (!writing[k]) local[k] = std::make_unique<KeptSlabArrays>(tile_samples, capacity[k]);
          const bool surfaces = z.stages[k].kind == ZslabStage::Kind::surfaces;
          std::span<Slab> mine(own, static_cast<size_t>(capacity[k]));
          for_each_sample(z, tile, [&](int x, int y, const Ray& ray, size_t i) {
            const size_t g = (static_cast<size_t>(y) * w + x) * spx + i % spx;
            std::span<const Fragment> f =
                surfaces ? fragments[k].of(i) : std::span<const Fragment>();
            int m = 0;
            if (!surfaces || !f.empty())
              m = z.own_slabs(k, x, y, ray, f, mine, clip_row(clip, have_clip, i));
            if (writing[k])
              writing[k]->store(g, mine.first(static_cast<size_t>(m)));
            else
              local[k]->store(i, mine.first(static_cast<size_t>(m)));
          });
        }
        // Then per sample the merges in stage order and the final accumulation (or cast).
        glm::vec4 sum(0.0f);
        for_each_sample(z, tile, [&](int x, int y, const Ray& ray, size_t i) {
          const size_t g = (static_cast<size_t>(y) * w + x) * spx + i % spx;
          const std::span<const Fragment> clip_i = clip_row(clip, have_clip, i);
          int cur = 0;
          int count = start > 0 ? prefix->load(g, run[0]) : 0;
          for (size_t k = start; k < end; ++k) {
            const bool surfaces = z.stages[k].kind == ZslabStage::Kind::surfaces;
            std::span<const Fragment> f =
                render_stage[k] && surfaces ? fragments[k].of(i) : std::span<const Fragment>();
            std::span<const Slab> stored(run[cur], static_cast<size_t>(count));
            SlabList out(std::span<Slab>(run[1 - cur], static_cast<size_t>(n)));
            bool touched = false;
            if (capacity[k] == 0) {  // not split: the whole stage, from its fragments
              touched =
                  (!surfaces || !f.empty()) && z.run_deferred(k, x, y, ray, f, stored, out, clip_i);
            } else {
              std::span<Slab> mine(own, static_cast<size_t>(capacity[k]));
              const int m = matched[k]   ? matched[k]->load(g, mine)
                            : writing[k] ? writing[k]->load(g, mine)
                                         : local[k]->load(i, mine);
              touched = z.merge_own(k, stored, mine.first(static_cast<size_t>(m)), out);
            }
            if (touched) {
              count = as_stored(std::span<Slab>(run[1 - cur], static_cast<size_t>(out.size())),
                                z.format);
              cur = 1 - cur;
            }
            if (write_prefix && k + 1 == first)
              prefix->store(g, std::span<const Slab>(run[cur], static_cast<size_t>(count)));
          }
          sum += z.run_final(end, x, y, ray, std::span<const Slab>(run[cur], count), clip_i);
          if (i % spx + 1 == spx) {
            image->at(x, y) = over_background(sum * weight, scene.image.background);
            sum = glm::vec4(0.0f);
          }
        });
      },
      [&](int done, int all) { report(options, done, all); });

  // Refill the cache: the own arrays rendered and kept, the prefix, the image.
  for (size_t k = start; k < end; ++k)
    if (writing[k]) {
      ZslabStageCache::Kept e{own_key[k], writing[k], {}};
      keep_alive_of(scene, z.stages[k], e.keep_alive);
      cache.own.push_back(std::move(e));
    }
  if (write_prefix) {
    cache.prefix = {chain[first], prefix, {}};
    cache.prefix_stage = first;
    for (size_t k = 0; k < first; ++k) keep_alive_of(scene, z.stages[k], cache.prefix.keep_alive);
  }
  if (end < z.stages.size()) {
    ++st.stages_run;
    st.recast_unchanged = cache.last_key == own_key[end] && first < end;
    cache.last_key = own_key[end];
  } else {
    cache.last_key = 0;
  }
  cache.image = image;
  cache.image_key = image_key;
  finish_stats();
  return *image;
}

}  // namespace imx
