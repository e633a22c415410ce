// VoxelBuffer: owned values or a zero-copy view of external memory (issue 21: numpy volumes),
// with copy on write, and a VolumeData built on a view behaving like one that owns its voxels.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <numeric>
#include <utility>
#include <vector>

#include "intermix/volume.hpp"
#include "intermix/voxel_buffer.hpp"
#include "volume/any_grid.hpp"

namespace imx {
namespace {

// External memory as Python would hand it over: an array behind a shared owner whose deleter
// says when it ran.
struct External {
  std::shared_ptr<const void> owner;
  const float* data = nullptr;
  size_t size = 0;
};

External external_floats(size_t n, bool* freed) {
  auto* values = new std::vector<float>(n);
  std::iota(values->begin(), values->end(), 1.0f);
  External e;
  e.data = values->data();
  e.size = n;
  e.owner = std::shared_ptr<const void>(values, [freed](const std::vector<float>* v) {
    *freed = true;
    delete v;
  });
  return e;
}

VolumeData volume_viewing(const External& e, glm::ivec3 dims) {
  VolumeData v;
  v.dims = dims;
  v.voxels = VoxelBuffer<float>::view(e.data, e.size, e.owner);
  return v;
}

TEST(VoxelBuffer, OwnsWhatItIsGivenWithoutCopying) {
  std::vector<int16_t> values = {3, -1, 4, 1, -5};
  const int16_t* where = values.data();
  VoxelBuffer<int16_t> b(std::move(values));
  EXPECT_TRUE(b.owns());
  EXPECT_EQ(b.data(), where);
  ASSERT_EQ(b.size(), 5u);
  EXPECT_EQ(b[2], 4);
  EXPECT_EQ(std::vector<int16_t>(b.begin(), b.end()), (std::vector<int16_t>{3, -1, 4, 1, -5}));

  // Assigning a moved vector to a volume keeps its memory too.
  std::vector<uint16_t> more(64, 7);
  const uint16_t* more_where = more.data();
  VolumeData v;
  v.voxels = std::move(more);
  EXPECT_EQ(v.type(), VoxelType::u16);
  EXPECT_EQ(std::get<VoxelBuffer<uint16_t>>(v.voxels).data(), more_where);

  EXPECT_TRUE(VoxelBuffer<float>().empty());
  EXPECT_TRUE(VoxelBuffer<float>().owns());
}

TEST(VoxelBuffer, AViewReadsTheExternalMemoryWithoutCopying) {
  bool freed = false;
  External e = external_floats(24, &freed);
  auto b = VoxelBuffer<float>::view(e.data, e.size, e.owner);
  EXPECT_FALSE(b.owns());
  EXPECT_EQ(b.data(), e.data);
  EXPECT_EQ(b.size(), 24u);
  EXPECT_EQ(b.begin(), e.data);
  EXPECT_EQ(b.end(), e.data + 24);
  EXPECT_EQ(&b[5], e.data + 5);
  EXPECT_EQ(b[5], 6.0f);
}

TEST(VoxelBuffer, AViewKeepsItsOwnerAliveAndCopiesShareIt) {
  bool freed = false;
  External e = external_floats(8, &freed);
  std::weak_ptr<const void> watch = e.owner;
  auto b = std::make_unique<VoxelBuffer<float>>(
      VoxelBuffer<float>::view(e.data, e.size, std::move(e.owner)));
  EXPECT_EQ(watch.use_count(), 1);
  EXPECT_FALSE(freed);

  auto copy = std::make_unique<VoxelBuffer<float>>(*b);
  EXPECT_EQ(watch.use_count(), 2);
  EXPECT_EQ(copy->data(), e.data) << "a copy of a view is a view";
  EXPECT_FALSE(copy->owns());

  b.reset();
  EXPECT_FALSE(freed) << "the copy still views the memory";
  VoxelBuffer<float> moved = std::move(*copy);
  EXPECT_EQ(moved.data(), e.data);
  EXPECT_TRUE(copy->empty()) << "a moved-from buffer is empty";
  EXPECT_EQ(watch.use_count(), 1);
  copy.reset();
  EXPECT_FALSE(freed);
  EXPECT_EQ(moved[7], 8.0f);

  moved = VoxelBuffer<float>(std::vector<float>{1.0f});  // the last view goes
  EXPECT_TRUE(freed);
  EXPECT_TRUE(moved.owns());
}

TEST(VoxelBuffer, CopyingAVolumeKeepsViewingTheSameMemory) {
  bool freed = false;
  External e = external_floats(2 * 3 * 4, &freed);
  std::weak_ptr<const void> watch = e.owner;
  auto a = std::make_unique<VolumeData>(volume_viewing(e, {2, 3, 4}));
  e.owner.reset();
  VolumeData b = *a;
  VolumeData c;
  c = b;
  for (const VolumeData* v : {a.get(), &b, &c}) {
    const auto& voxels = std::get<VoxelBuffer<float>>(v->voxels);
    EXPECT_EQ(voxels.data(), e.data);
    EXPECT_FALSE(voxels.owns());
    // What samplers read goes through data(): the external memory itself.
    EXPECT_EQ(AnyGrid(*v).data, static_cast<const void*>(e.data));
  }
  EXPECT_EQ(watch.use_count(), 3);
  a.reset();
  EXPECT_EQ(watch.use_count(), 2);
  EXPECT_FALSE(freed);

  // A volume on a view is a volume like any other.
  EXPECT_NO_THROW(c.validate("view"));
  EXPECT_EQ(c.voxel_count(), 24u);
  EXPECT_EQ(c.value_at(1, 2, 3), 24.0);
  EXPECT_EQ(c.range(), (std::pair<double, double>{1.0, 24.0}));
}

TEST(VoxelBuffer, CopyingOwnedValuesCopiesThem) {
  VoxelBuffer<uint8_t> a(std::vector<uint8_t>{1, 2, 3});
  VoxelBuffer<uint8_t> b = a;
  EXPECT_TRUE(b.owns());
  EXPECT_NE(b.data(), a.data());
  EXPECT_EQ(a, b);
  b.mutable_data()[0] = 9;
  EXPECT_EQ(a[0], 1);
  EXPECT_EQ(b[0], 9);
  a = b;
  EXPECT_NE(a.data(), b.data());
  EXPECT_EQ(a[0], 9);

  const uint8_t* where = a.data();
  VoxelBuffer<uint8_t> c = std::move(a);
  EXPECT_EQ(c.data(), where) << "moving owned values moves their memory";
  EXPECT_TRUE(a.empty());  // a moved-from buffer is empty
}

TEST(VoxelBuffer, WritingThroughAViewCopiesFirst) {
  bool freed = false;
  External e = external_floats(6, &freed);
  std::weak_ptr<const void> watch = e.owner;
  const std::vector<float> before(e.data, e.data + e.size);
  auto b = VoxelBuffer<float>::view(e.data, e.size, e.owner);
  const auto other = b;  // another view, made before the write
  e.owner.reset();
  EXPECT_EQ(watch.use_count(), 2);

  float* w = b.mutable_data();
  EXPECT_NE(w, e.data);
  EXPECT_TRUE(b.owns());
  EXPECT_EQ(b.data(), w);
  EXPECT_EQ(watch.use_count(), 1) << "the writer let go of the owner";
  EXPECT_EQ(std::vector<float>(b.begin(), b.end()), before) << "the copy has the same values";
  w[0] = -100.0f;
  w[5] = 42.0f;
  EXPECT_EQ(b[0], -100.0f);
  EXPECT_EQ(std::vector<float>(e.data, e.data + e.size), before)
      << "the external memory is untouched";
  EXPECT_EQ(other.data(), e.data);
  EXPECT_EQ(other[0], 1.0f);
  EXPECT_EQ(b.mutable_data(), w) << "owned values are written in place";
  EXPECT_FALSE(freed);
}

TEST(VoxelBuffer, EqualityIsElementWise) {
  bool freed = false;
  External e = external_floats(4, &freed);
  auto view = VoxelBuffer<float>::view(e.data, e.size, e.owner);
  VoxelBuffer<float> owned(std::vector<float>{1.0f, 2.0f, 3.0f, 4.0f});
  EXPECT_EQ(view, owned);
  EXPECT_EQ(owned, view);
  EXPECT_NE(view, VoxelBuffer<float>(std::vector<float>{1.0f, 2.0f, 3.0f, 5.0f}));
  EXPECT_NE(view, VoxelBuffer<float>(std::vector<float>{1.0f, 2.0f, 3.0f}));
  EXPECT_NE(view, VoxelBuffer<float>::view(e.data, 3, e.owner));
  EXPECT_EQ(VoxelBuffer<float>(), VoxelBuffer<float>::view(nullptr, 0, nullptr));

  // And through VolumeData's variant: a volume on a view equals one owning the same values.
  VolumeData a = volume_viewing(e, {4, 1, 1});
  VolumeData b;
  b.dims = {4, 1, 1};
  b.voxels = std::vector<float>{1.0f, 2.0f, 3.0f, 4.0f};
  EXPECT_TRUE(a.voxels == b.voxels);
  b.voxels = std::vector<uint8_t>{1, 2, 3, 4};
  EXPECT_FALSE(a.voxels == b.voxels) << "other types never compare equal";
}

}  // namespace
}  // namespace imx
