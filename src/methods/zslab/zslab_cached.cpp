// render_zslab_cached (SPEC §4, reuse): the frame's keys, its reuse plan (zslab_reuse_plan.hpp),
// the arrays the plan names taken from the cache, the tiles, then the cache refilled.
#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "core/colour.hpp"
#include "intermix/limits.hpp"
#include "methods/zslab/stage_hash.hpp"
#include "methods/zslab/zslab.hpp"
#include "methods/zslab/zslab_frame.hpp"
#include "methods/zslab/zslab_kept.hpp"
#include "methods/zslab/zslab_object_kernel.hpp"
#include "methods/zslab/zslab_reuse_plan.hpp"
#include "methods/zslab/zslab_tile_loop.hpp"

namespace imx {

using zslab_tiles::clip_row;
using zslab_tiles::for_each_sample;

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
    if (ref.kind == ObjectKind::streamlines) {
      out.push_back(scene.streamlines[ref.index].streamlines);
      for (const ClipMesh& c : scene.streamlines[ref.index].clip_meshes)
        out.push_back(scene.meshes[c.mesh].mesh);
    }
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

// Own keys hash the frame and the stage's own content only; the chain key of stage k hashes the
// stages before it, the image key all of them and the background.
struct FrameKeys {
  std::vector<uint64_t> own, chain;
  uint64_t image = 0;
};

FrameKeys frame_keys(const ZslabFrame& z) {
  FrameKeys keys;
  keys.own.resize(z.stages.size());
  keys.chain.resize(z.stages.size() + 1);
  keys.chain[0] = z.frame_key();
  for (size_t k = 0; k < z.stages.size(); ++k) {
    keys.own[k] = StageHash().add(z.frame_key()).add(z.stages[k].content).value();
    keys.chain[k + 1] = StageHash().add(keys.chain[k]).add(z.stages[k].content).value();
  }
  keys.image = StageHash().add(keys.chain.back()).add(z.scene.image.background).value();
  return keys;
}

// What the plan needs of the frame's first `end` (deferred) stages and of the cache.
ZslabReuseInput reuse_input(const ZslabFrame& z, const FrameKeys& keys, size_t end, size_t samples,
                            const ZslabStageCache& cache) {
  ZslabReuseInput in;
  in.own_key.assign(keys.own.begin(), keys.own.begin() + static_cast<std::ptrdiff_t>(end));
  in.chain.assign(keys.chain.begin(), keys.chain.begin() + static_cast<std::ptrdiff_t>(end + 1));
  for (size_t k = 0; k < end; ++k) in.capacity.push_back(z.own_capacity(k));
  in.samples = samples;
  in.layers = z.params.layers;
  in.budget = cache.budget_bytes;
  for (const ZslabStageCache::Kept& e : cache.own) {
    in.kept_own.emplace_back();
    if (e.slabs)
      in.kept_own.back() = KeptArrayShape{e.key, e.slabs->samples(), e.slabs->capacity()};
  }
  if (cache.prefix.slabs)
    in.prefix = KeptArrayShape{cache.prefix.key, cache.prefix.slabs->samples(),
                               cache.prefix.slabs->capacity()};
  in.prefix_stage = cache.prefix_stage;
  return in;
}

// The arrays a frame reads and writes, per deferred stage, and the merged prefix.
struct FrameArrays {
  std::vector<std::shared_ptr<KeptSlabArrays>> matched, writing;
  std::shared_ptr<KeptSlabArrays> prefix;
};

// Takes what the plan names from `cache`: the matched own arrays stay listed there, the others
// become storage for this frame's recomputed ones (and a new prefix); the cache lets its prefix
// go when the plan says so.
FrameArrays take_arrays(const ZslabReusePlan& plan, const ZslabReuseInput& in,
                        ZslabStageCache& cache) {
  const size_t end = plan.keep.size();
  FrameArrays a;
  a.matched.resize(end);
  a.writing.resize(end);
  std::vector<ZslabStageCache::Kept> old = std::move(cache.own);
  cache.own.clear();
  for (size_t k = 0; k < end; ++k)
    if (plan.matched[k] >= 0) {
      ZslabStageCache::Kept& e = old[static_cast<size_t>(plan.matched[k])];
      a.matched[k] = e.slabs;
      cache.own.push_back(std::move(e));
    }
  std::vector<std::shared_ptr<KeptSlabArrays>> pool;
  for (auto& e : old)
    if (e.slabs) pool.push_back(std::move(e.slabs));
  if (plan.read_prefix) a.prefix = cache.prefix.slabs;
  if (plan.drop_prefix) cache.prefix = {};  // a valid one is still read this frame
  // written in place: each sample reads, then writes
  if (plan.write_prefix && !a.prefix) a.prefix = take(pool, in.samples, in.layers);
  for (size_t k = plan.start; k < end; ++k)
    if (plan.render[k] && plan.keep[k]) a.writing[k] = take(pool, in.samples, in.capacity[k]);
  return a;
}

// One frame's tile work: what it reads, and where a tile's sample lives in the frame's arrays.
struct CachedRun {
  const ZslabFrame& z;
  const ZslabReusePlan& plan;
  const std::vector<int>& capacity;
  const FrameArrays& arrays;
  bool clip_needed;
  size_t end, spx;
  int width;
  size_t global(int x, int y, size_t i) const {
    return (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * spx +
           i % spx;
  }
};

// What a tile rasterized: the fragments of the surface stages it renders, the clip meshes'.
struct TileInputs {
  std::vector<SampleFragments> fragments;
  SampleFragments clip;
  bool have_clip = false;
  std::vector<std::unique_ptr<KeptSlabArrays>> local;  // evicted stages' own arrays, tile-local
};

// Each object to render, stage by stage over the tile (one volume's bricks stay in cache), into
// its kept array or, when evicted, a tile-local one.
void render_objects(const CachedRun& r, const TileRect& tile, TileInputs& in) {
  Slab own[std::max(kMaxOwnSurfaceSlabs, kMaxZslabLayers)];
  const size_t tile_samples =
      static_cast<size_t>(tile.width()) * static_cast<size_t>(tile.height()) * r.spx;
  for (size_t k = r.plan.start; k < r.end; ++k) {
    if (!r.plan.render[k] || r.capacity[k] == 0) continue;
    KeptSlabArrays* writing = r.arrays.writing[k].get();
    if (!writing) in.local[k] = std::make_unique<KeptSlabArrays>(tile_samples, r.capacity[k]);
    const bool surfaces = r.z.stages[k].kind == ZslabStage::Kind::surfaces;
    if (!surfaces && r.z.volume_stage_in_packets(k)) {  // the whole tile in lanes
      zslab_tiles::OwnVolumeSlabs lanes(tile_samples, r.z.params.layers);
      r.z.own_volume_slabs(k, tile, lanes.lists);
      zslab_tiles::for_each_sample_index(r.z, tile, [&](int x, int y, size_t i) {
        const std::span<const Slab> slabs = lanes.lists[i].items();
        if (writing)
          writing->store(r.global(x, y, i), slabs);
        else
          in.local[k]->store(i, slabs);
      });
      continue;
    }
    std::span<Slab> mine(own, static_cast<size_t>(r.capacity[k]));
    auto run = [&](int x, int y, const Ray& ray, size_t i) {
      std::span<const Fragment> f = surfaces ? in.fragments[k].of(i) : std::span<const Fragment>();
      int m = 0;
      if (!surfaces || !f.empty())
        m = r.z.own_slabs(k, x, y, ray, f, mine, clip_row(in.clip, in.have_clip, i));
      if (writing)
        writing->store(r.global(x, y, i), mine.first(static_cast<size_t>(m)));
      else
        in.local[k]->store(i, mine.first(static_cast<size_t>(m)));
    };
    if (surfaces) {
      const Ray unused{};  // a surface stage reads its fragments, not the ray
      zslab_tiles::for_each_sample_index(r.z, tile,
                                         [&](int x, int y, size_t i) { run(x, y, unused, i); });
    } else {
      for_each_sample(r.z, tile, run);
    }
  }
}

// Sample i's merges in stage order, from the kept prefix or from nothing (storing the new
// prefix where the plan writes one), into `merged` (N slots): returns how many.
int merge_sample(const CachedRun& r, const TileInputs& in, int x, int y, const Ray& ray, size_t i,
                 std::span<Slab> merged) {
  SlabScratch<kMaxZslabLayers> run[2];
  SlabScratch<std::max(kMaxOwnSurfaceSlabs, kMaxZslabLayers)> own;
  const ZslabReusePlan& plan = r.plan;
  const size_t g = r.global(x, y, i);
  const std::span<const Fragment> clip_i = clip_row(in.clip, in.have_clip, i);
  int cur = 0;
  int count = plan.start > 0 ? r.arrays.prefix->load(g, run[0].span()) : 0;
  for (size_t k = plan.start; k < r.end; ++k) {
    const bool surfaces = r.z.stages[k].kind == ZslabStage::Kind::surfaces;
    std::span<const Fragment> f =
        plan.render[k] && surfaces ? in.fragments[k].of(i) : std::span<const Fragment>();
    std::span<const Slab> stored(run[cur].data(), static_cast<size_t>(count));
    SlabList out(run[1 - cur].span(r.z.params.layers));
    bool touched = false;
    if (r.capacity[k] == 0) {  // not split: the whole stage, from its fragments
      touched = (!surfaces || !f.empty()) && r.z.run_deferred(k, x, y, ray, f, stored, out, clip_i);
    } else {
      std::span<Slab> mine = own.span(r.capacity[k]);
      const int m = r.arrays.matched[k]   ? r.arrays.matched[k]->load(g, mine)
                    : r.arrays.writing[k] ? r.arrays.writing[k]->load(g, mine)
                                          : in.local[k]->load(i, mine);
      touched = r.z.merge_own(k, stored, mine.first(static_cast<size_t>(m)), out);
    }
    if (touched) {
      count = as_stored(run[1 - cur].span(out.size()), r.z.format);
      cur = 1 - cur;
    }
    if (plan.write_prefix && k + 1 == plan.first)
      r.arrays.prefix->store(g, std::span<const Slab>(run[cur].data(), static_cast<size_t>(count)));
  }
  std::copy_n(run[cur].data(), count, merged.begin());
  return count;
}

// A tile: its rasterization, then each object to render, then per sample the merges; the
// pixels' samples averaged over the background into `image`.
void run_tile(const CachedRun& r, const TileRect& tile, Image& image) {
  TileInputs in;
  in.fragments.resize(r.end);
  in.local.resize(r.end);
  for (size_t k = r.plan.start; k < r.end; ++k)
    if (r.plan.render[k] && r.z.stages[k].kind == ZslabStage::Kind::surfaces)
      r.z.rasterize(k, tile, in.fragments[k]);
  in.have_clip = r.clip_needed && r.z.rasterize_clip(tile, in.clip);
  render_objects(r, tile, in);
  // The last volume cast on the fly takes the whole tile at once in lanes where it can: every
  // sample's merged array first, then the cast. Else each sample is merged and finished in turn.
  std::vector<Slab> slots;
  std::vector<std::span<const Slab>> merged;
  std::vector<glm::vec4> cast;
  if (r.z.final_stage_in_lanes(r.end)) {
    const size_t samples = static_cast<size_t>(tile.width()) * tile.height() * r.spx;
    const size_t n = static_cast<size_t>(r.z.params.layers);
    slots.resize(samples * n);
    merged.resize(samples);
    for_each_sample(r.z, tile, [&](int x, int y, const Ray& ray, size_t i) {
      std::span<Slab> mine = std::span<Slab>(slots).subspan(i * n, n);
      merged[i] = mine.first(static_cast<size_t>(merge_sample(r, in, x, y, ray, i, mine)));
    });
    cast.resize(samples);
    r.z.run_final_in_lanes(r.end, tile, merged, cast);
  }
  const float weight = 1.0f / static_cast<float>(r.spx);
  const glm::vec4 background = r.z.scene.image.background;
  glm::vec4 sum(0.0f);
  for_each_sample(r.z, tile, [&](int x, int y, const Ray& ray, size_t i) {
    if (!cast.empty()) {
      sum += cast[i];
    } else {
      SlabScratch<kMaxZslabLayers> mine;
      const int count = merge_sample(r, in, x, y, ray, i, mine.span());
      sum += r.z.run_final(r.end, x, y, ray, std::span<const Slab>(mine.data(), count),
                           clip_row(in.clip, in.have_clip, i));
    }
    if (i % r.spx + 1 == r.spx) {
      image.at(x, y) = over_background(sum * weight, background);
      sum = glm::vec4(0.0f);
    }
  });
}

// Refills the cache after the frame: the own arrays rendered and kept, the prefix, the image.
void refill(const ZslabFrame& z, const ZslabReusePlan& plan, const FrameKeys& keys,
            const FrameArrays& arrays, ZslabStageCache& cache) {
  const size_t end = plan.keep.size();
  for (size_t k = plan.start; k < end; ++k)
    if (arrays.writing[k]) {
      ZslabStageCache::Kept e{keys.own[k], arrays.writing[k], {}};
      keep_alive_of(z.scene, z.stages[k], e.keep_alive);
      cache.own.push_back(std::move(e));
    }
  if (plan.write_prefix) {
    cache.prefix = {keys.chain[plan.first], arrays.prefix, {}};
    cache.prefix_stage = plan.first;
    for (size_t k = 0; k < plan.first; ++k)
      keep_alive_of(z.scene, z.stages[k], cache.prefix.keep_alive);
  }
}

}  // namespace

Image render_zslab_cached(const Scene& scene, int spp, const RenderOptions& options, bool hybrid,
                          ZslabStageCache& cache, ZslabStats* stats) {
  ZslabFrame z(scene, spp, hybrid, options.sample_index);
  const size_t end = zslab_tiles::deferred_end(z);
  const int w = scene.image.width, h = scene.image.height;
  const size_t spx = z.offsets.size();
  const FrameKeys keys = frame_keys(z);

  ZslabStats st;
  st.stages = static_cast<int>(z.stages.size());
  st.stream_bytes_per_pixel = zslab_stream_bytes_per_sample(scene.render) * spx;
  auto finish_stats = [&]() {
    st.kept_bytes_per_pixel =
        static_cast<double>(cache.kept_bytes()) / (static_cast<double>(w) * h);
    if (stats) *stats = st;
  };
  if (cache.image && cache.image_key == keys.image) {
    finish_stats();
    return *cache.image;
  }
  if (zslab_in_packets(z)) {  // one stage, nothing to keep but the image
    auto image = std::make_shared<Image>(render_zslab_packets(z, options));
    st.stages_run = 1;
    st.recast_unchanged = cache.last_key == keys.own[0];
    cache.last_key = keys.own[0];
    cache.image = image;
    cache.image_key = keys.image;
    finish_stats();
    return *image;
  }

  const ZslabReuseInput input = reuse_input(z, keys, end, static_cast<size_t>(w) * h * spx, cache);
  const ZslabReusePlan plan = plan_zslab_reuse(input);
  const FrameArrays arrays = take_arrays(plan, input, cache);
  st.stages_run = plan.stages_run();
  st.stages_merged = plan.stages_merged();
  check_memory(plan.kept_bytes(),
               fmt::format("zslab's kept slab arrays for {}x{} pixels at {} spp", w, h, spx));
  z.prepare(plan.first);

  bool clip_needed = zslab_tiles::clipped_stage(z, end);
  for (size_t k = plan.start; k < end; ++k)
    clip_needed = clip_needed || (plan.render[k] && zslab_tiles::clipped_stage(z, k));
  const CachedRun run{z, plan, input.capacity, arrays, clip_needed, end, spx, w};
  auto image = std::make_shared<Image>(w, h);
  for_each_tile(
      w, h, zslab_tiles::kTileSize, options.threads,
      [&](const TileRect& tile, int) { run_tile(run, tile, *image); },
      [&](int done, int all) { zslab_tiles::report(options, done, all); });

  refill(z, plan, keys, arrays, cache);
  if (end < z.stages.size()) {
    ++st.stages_run;
    st.recast_unchanged = cache.last_key == keys.own[end] && plan.first < end;
    cache.last_key = keys.own[end];
  } else {
    cache.last_key = 0;
  }
  cache.image = image;
  cache.image_key = keys.image;
  finish_stats();
  return *image;
}

}  // namespace imx
