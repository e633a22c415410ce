#include "methods/zslab/zslab.hpp"

#include <optional>
#include <vector>

#include "core/colour.hpp"
#include "core/parallel.hpp"
#include "methods/mdvr/mdvr.hpp"
#include "methods/zslab/zslab_frame.hpp"
#include "methods/zslab/zslab_tile_loop.hpp"
#include "slab/zt_buffer.hpp"

namespace imx {

namespace {

using zslab_tiles::clip_row;
using zslab_tiles::deferred_end;
using zslab_tiles::for_each_sample;
using zslab_tiles::for_each_sample_index;
using zslab_tiles::kTileSize;
using zslab_tiles::OwnVolumeSlabs;
using zslab_tiles::report;

// Stateless pipeline: every stage runs on one tile's ping-pong ZT-buffers before the next tile;
// a flag bit per sample says which of the two holds its array (untouched samples cost nothing).
// With `arrays`, every stage is deferred and each sample's array is stored there instead of
// composited (the image is then left empty).
Image render_streamed(const Scene& scene, int spp, const RenderOptions& options, bool hybrid,
                      ZtBuffer* arrays = nullptr) {
  ZslabFrame z(scene, spp, hybrid, options.sample_index);
  if (!arrays && zslab_in_packets(z)) return render_zslab_packets(z, options);
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
        std::optional<OwnVolumeSlabs> own;  // made when a volume stage or the cast needs it
        for (size_t k = 0; k < end; ++k) {
          const bool surfaces = z.stages[k].kind == ZslabStage::Kind::surfaces;
          if (surfaces && !z.stage_reaches(k, tile)) continue;  // no fragment here: untouched
          if (surfaces) z.rasterize(k, tile, fragments);
          if (!surfaces && z.volume_stage_in_packets(k)) {
            // The volume's own arrays of the whole tile in lanes, then each merged as
            // run_deferred merges it.
            if (!own) own.emplace(samples, n);
            z.own_volume_slabs(k, tile, own->lists);
            for (size_t i = 0; i < samples; ++i) {
              if (own->lists[i].size() == 0) continue;
              uint32_t c = current(i);
              int count = zt[c].load(i, in_slots);
              SlabList out(std::span<Slab>(out_slots, static_cast<size_t>(n)));
              z.merge_own(k, std::span<const Slab>(in_slots, count), own->lists[i].items(), out);
              zt[1 - c].store(i, out.items());
              flags[i / 32] ^= 1u << (i % 32);
            }
            continue;
          }
          auto run = [&](int x, int y, const Ray& ray, size_t i) {
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
          };
          if (surfaces) {
            const Ray unused{};  // a surface stage reads its fragments, not the ray
            for_each_sample_index(z, tile, [&](int x, int y, size_t i) { run(x, y, unused, i); });
          } else {
            for_each_sample(z, tile, run);
          }
        }
        if (arrays) {
          const size_t per_pixel = z.offsets.size();
          for_each_sample(z, tile, [&](int x, int y, const Ray&, size_t i) {
            size_t pixel = static_cast<size_t>(y) * w + x;
            arrays->copy(pixel * per_pixel + i % per_pixel, zt[current(i)], i);
          });
          return;
        }
        // The last volume cast on the fly: a tile's samples at once in lanes where it can.
        std::vector<glm::vec4> cast;
        if (z.final_stage_in_lanes(end)) {
          std::vector<std::span<const Slab>> stored(samples);
          if (!own) own.emplace(samples, n);
          for (size_t i = 0; i < samples; ++i) {
            Slab* slots = own->slots.data() + i * static_cast<size_t>(n);
            stored[i] = std::span<const Slab>(
                slots, static_cast<size_t>(
                           zt[current(i)].load(i, std::span<Slab>(slots, static_cast<size_t>(n)))));
          }
          cast.resize(samples);
          z.run_final_in_lanes(end, tile, stored, cast);
        }
        glm::vec4 sum(0.0f);
        size_t done = 0;
        for_each_sample(z, tile, [&](int x, int y, const Ray& ray, size_t i) {
          if (!cast.empty()) {
            sum += cast[i];
          } else {
            int count = zt[current(i)].load(i, in_slots);
            sum += z.run_final(end, x, y, ray, std::span<const Slab>(in_slots, count),
                               clip_row(clip, have_clip, i));
          }
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

bool zslab_in_packets(const ZslabFrame& z) {
  return z.format == SlabFormat::rgba32f && volume_packets_apply(z.scene, z.frame);
}

Image render_zslab_packets(const ZslabFrame& z, const RenderOptions& options) {
  MdvrParams p;
  p.step = z.steps[0];
  p.ert = z.params.mix.a_ert;
  p.iso_bisections = kZslabIsoBisections;
  return render_volume_packets(z.scene, z.frame, p, SlabExtent::visible, options, z.offsets);
}

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

}  // namespace imx
