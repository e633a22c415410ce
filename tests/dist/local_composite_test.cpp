// The distributed pipeline in one process: each rank's part loaded by region and rendered into
// slab arrays, the arrays traded and merged by the binary-swap schedule as MPI would carry
// them, and the resolved pixels compared with the single-process zslab image.
#include <gtest/gtest.h>

#include "dist/rank_scene.hpp"
#include "dist/slab_message.hpp"
#include "dist/swap_schedule.hpp"
#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "methods/zslab.hpp"
#include "methods/zslab_frame.hpp"

namespace imx {
namespace {

const std::vector<std::string> kSmall = {"image.width=64", "image.height=64"};

// `cut` false: bricks render their aprons too, as a wrong cut would.
Image render_split(const std::string& scene_file, int ranks, PartitionMode mode, bool cut = true,
                   const std::vector<std::string>& overrides = kSmall) {
  Scene outline = load_scene(scene_file, overrides, [](const std::string&, const VolumeHeader&) {
    return VoxelBox{glm::ivec3(0), glm::ivec3(1)};
  });
  Partition partition = plan_partition(outline, ranks, mode);
  if (!cut)
    for (RankPart& part : partition.ranks)
      for (auto& [name, brick] : part.bricks) brick.bounds.clear();
  std::vector<ZtBuffer> arrays(static_cast<size_t>(ranks));
  for (int r = 0; r < ranks; ++r) {
    Scene part = rank_scene(load_scene(scene_file, overrides, rank_regions(partition, r, outline)),
                            partition, r);
    render_zslab_arrays(part, 1, RenderOptions{}, arrays[static_cast<size_t>(r)]);
  }
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

TEST(LocalComposite, ThreeRanksFoldBeforeSwapping) {
  const std::string file = std::string(IMX_EXAMPLES_DIR) + "/two-volumes.json";
  EXPECT_GE(psnr(render_whole(file), render_split(file, 3, PartitionMode::bricks)), 45.0);
}

}  // namespace
}  // namespace imx
