// The distributed pipeline in one process: each rank's part loaded by region and rendered into
// slab arrays, the arrays traded and merged by the binary-swap schedule as MPI would carry
// them, and the resolved pixels compared with the single-process zslab image.
#include <gtest/gtest.h>

#include "core/colour.hpp"
#include "dist/rank_scene.hpp"
#include "dist/slab_message.hpp"
#include "dist/swap_schedule.hpp"
#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "methods/zslab/zslab.hpp"
#include "slab/accumulate.hpp"
#include "slab/over.hpp"

#include <algorithm>
#include <utility>

namespace imx {
namespace {

const std::vector<std::string> kSmall = {"image.width=64", "image.height=64"};

struct RankArrays {
  Scene outline;
  std::vector<ZtBuffer> arrays;  // per rank
};

// Every rank's part loaded by region and rendered. `cut` false: bricks render their aprons
// too, as a wrong cut would.
RankArrays render_ranks(const std::string& scene_file, int ranks, PartitionMode mode,
                        bool cut = true) {
  RankArrays out;
  out.outline = load_scene(scene_file, kSmall, [](const std::string&, const VolumeHeader&) {
    return VoxelBox{glm::ivec3(0), glm::ivec3(1)};
  });
  Partition partition = plan_partition(out.outline, ranks, mode);
  if (!cut)
    for (RankPart& part : partition.ranks)
      for (auto& [name, brick] : part.bricks) brick.bounds.clear();
  out.arrays.resize(static_cast<size_t>(ranks));
  for (int r = 0; r < ranks; ++r) {
    Scene part = rank_scene(load_scene(scene_file, kSmall, rank_regions(partition, r, out.outline)),
                            partition, r);
    render_zslab_arrays(part, 1, RenderOptions{}, out.arrays[static_cast<size_t>(r)]);
  }
  return out;
}

// The ranks' arrays traded and merged by the binary-swap schedule, then resolved.
Image composite_deep(RankArrays parts) {
  const Scene& outline = parts.outline;
  std::vector<ZtBuffer>& arrays = parts.arrays;
  const int ranks = static_cast<int>(arrays.size());
  const size_t pixels = static_cast<size_t>(outline.image.width) * outline.image.height;
  const IntermixSettings mix = zslab_params(outline.render).mix;
  std::vector<SwapSchedule> plans;
  for (int r = 0; r < ranks; ++r) plans.push_back(binary_swap(ranks, r, pixels));
  for (int r = 0; r < ranks; ++r)
    if (plans[r].fold_to >= 0)
      merge_slab_message(arrays[plans[r].fold_to], {0, pixels}, 1,
                         encode_slab_message(arrays[r], {0, pixels}, 1), true, mix, 2);
  for (size_t k = 0; k < plans[0].rounds.size(); ++k) {
    // Every message of a round is encoded before any is merged, as the exchange does.
    std::vector<std::vector<std::byte>> sent(static_cast<size_t>(ranks));
    for (int r = 0; r < swap_group(ranks); ++r)
      sent[r] = encode_slab_message(arrays[r], plans[r].rounds[k].send, 1);
    for (int r = 0; r < swap_group(ranks); ++r) {
      const SwapRound& round = plans[r].rounds[k];
      merge_slab_message(arrays[r], round.keep, 1, sent[round.partner], round.first, mix, 2);
    }
  }
  Image image(outline.image.width, outline.image.height);
  for (int r = 0; r < swap_group(ranks); ++r) {
    std::vector<glm::vec4> px =
        resolve_slab_arrays(arrays[r], plans[r].result, 1, mix.a_ert, outline.image.background, 2);
    for (size_t p = 0; p < px.size(); ++p) {
      size_t at = plans[r].result.first + p;
      image.at(static_cast<int>(at % 64), static_cast<int>(at / 64)) = px[p];
    }
  }
  return image;
}

Image render_split(const std::string& scene_file, int ranks, PartitionMode mode, bool cut = true) {
  return composite_deep(render_ranks(scene_file, ranks, mode, cut));
}

// What a single-layer compositor (IceT's kind) can do with the same parts: each rank's arrays
// flattened to one colour and the depth of its nearest slab, the ranks then blended per pixel
// from near to far.
Image composite_single_layer(const RankArrays& parts) {
  const int w = parts.outline.image.width, h = parts.outline.image.height;
  const float a_ert = zslab_params(parts.outline.render).mix.a_ert;
  Image image(w, h);
  Slab slabs[kMaxZslabLayers];
  for (int p = 0; p < w * h; ++p) {
    std::vector<std::pair<float, glm::vec4>> layers;
    for (const ZtBuffer& b : parts.arrays) {
      int n = b.load(static_cast<size_t>(p), slabs);
      if (n > 0)
        layers.emplace_back(slabs[0].t_back - slabs[0].thickness,
                            accumulate(std::span<const Slab>(slabs, n), a_ert).color);
    }
    std::sort(layers.begin(), layers.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    glm::vec4 c(0.0f);
    for (const auto& layer : layers) c = over(c, layer.second);
    image.at(p % w, p / w) = over_background(c, parts.outline.image.background);
  }
  return image;
}

Image render_whole(const std::string& scene_file) {
  RenderOptions options;
  options.method = "zslab";
  return render(load_scene(scene_file, kSmall), options);
}

TEST(LocalComposite, FourBricksGiveTheUnsplitImage) {
  const std::string file = std::string(IMX_EXAMPLES_DIR) + "/ct-head.json";
  Image whole = render_whole(file);
  Image split = render_split(file, 4, PartitionMode::bricks);
  // The issue asks 50 dB; this split measures 86 dB, and a one-voxel overlap at the cuts (the
  // bricks rendering their aprons too) drops it to 56 dB, so 75 dB tells a right cut apart.
  EXPECT_GE(psnr(whole, split), 75.0);
  EXPECT_LT(psnr(whole, render_split(file, 4, PartitionMode::bricks, false)), 70.0);
}

TEST(LocalComposite, ObjectsOnTwoRanksGiveTheSingleProcessImage) {
  const std::string file = std::string(IMX_EXAMPLES_DIR) + "/fusion.json";
  EXPECT_GE(psnr(render_whole(file), render_split(file, 2, PartitionMode::objects)), 60.0);
}

// The comparison of docs/distributed.md: parts that overlap in depth (objects: CT and PET in
// the same place) cannot be put in one order, so one layer per rank fails where the deep arrays
// of the same parts composite correctly. Bricks are convex and disjoint, which single-layer
// compositing handles but for the translucent sphere crossing them (printed, not asserted).
TEST(LocalComposite, SingleLayerCompositingFailsWhereDeepSucceeds) {
  const std::string file = std::string(IMX_EXAMPLES_DIR) + "/fusion.json";
  Image whole = render_whole(file);
  for (PartitionMode mode : {PartitionMode::objects, PartitionMode::bricks}) {
    // Both compositors take the same rendered parts (the parts are most of the test's time).
    RankArrays parts = render_ranks(file, 3, mode);
    double single = psnr(whole, composite_single_layer(parts));
    double deep = psnr(whole, composite_deep(std::move(parts)));
    std::printf("fusion, 3 ranks by %s: deep %.1f dB, single layer %.1f dB against one process\n",
                partition_mode_name(mode), deep, single);
    EXPECT_GE(deep, 50.0);
    if (mode == PartitionMode::objects) {
      EXPECT_LT(single, deep - 20.0);
    }
  }
}

TEST(LocalComposite, ThreeRanksFoldBeforeSwapping) {
  const std::string file = std::string(IMX_EXAMPLES_DIR) + "/two-volumes.json";
  EXPECT_GE(psnr(render_whole(file), render_split(file, 3, PartitionMode::bricks)), 45.0);
}

}  // namespace
}  // namespace imx
