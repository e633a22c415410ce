// Volumes whose voxels are a view of external memory (VoxelBuffer::view, issue 21: numpy arrays
// without a copy) render byte for byte as the same voxels owned.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "intermix/voxel_buffer.hpp"

namespace imx {
namespace {

// The same volume with its voxels copied into memory held by a separate owner and viewed.
std::shared_ptr<VolumeData> as_view(const VolumeData& owned) {
  auto out = std::make_shared<VolumeData>(owned);
  std::visit(
      [&](const auto& values) {
        using T = typename std::decay_t<decltype(values)>::value_type;
        auto external = std::make_shared<const std::vector<T>>(values.begin(), values.end());
        out->voxels = VoxelBuffer<T>::view(external->data(), external->size(), external);
      },
      owned.voxels);
  return out;
}

const void* voxel_data(const VolumeData& v) {
  return std::visit([](const auto& b) { return static_cast<const void*>(b.data()); }, v.voxels);
}

bool owns(const VolumeData& v) {
  return std::visit([](const auto& b) { return b.owns(); }, v.voxels);
}

TEST(VoxelViewRender, AViewRendersByteIdenticalToOwnedVoxels) {
  Scene owned = load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "fusion.json",
                           {"image.width=40", "image.height=40", "objects.ct.source.size=40",
                            "objects.pet.source.size=40"});
  ASSERT_EQ(owned.volumes.size(), 2u);
  Scene viewed = owned;
  for (VolumeObject& v : viewed.volumes) {
    ASSERT_TRUE(owns(*v.data));
    auto view = as_view(*v.data);
    ASSERT_FALSE(owns(*view));
    ASSERT_NE(voxel_data(*view), voxel_data(*v.data));
    v.data = std::move(view);
  }
  EXPECT_NE(owned.volumes[0].data->type(), owned.volumes[1].data->type());

  RenderOptions options;
  options.method = "zslab";
  options.spp = 1;
  const Image a = render(owned, options);
  const Image b = render(viewed, options);
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  ASSERT_EQ(a.size(), 40u * 40u);
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(*a.data())), 0);
  // Not an empty picture that any two inputs would share.
  bool drawn = false;
  for (size_t i = 0; i < a.size(); ++i) drawn = drawn || a.data()[i] != owned.image.background;
  EXPECT_TRUE(drawn);
}

}  // namespace
}  // namespace imx
