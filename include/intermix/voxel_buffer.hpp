// VoxelBuffer<T>: a read-only array of voxel values that either owns them or views external
// memory (a numpy array, a mapped file) kept alive by a shared owner, with copy on write.
#pragma once
#include <algorithm>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

namespace imx {

// Reads are those of a const std::vector<T>: data() is one load, so samplers that take
// data() once run as fast on a view as on owned values. A copy of an owning buffer copies the
// values; a copy of a view is another view of the same memory, sharing its owner. Writes go
// through mutable_data(), which first copies a view into owned storage, so the viewed memory
// is never written.
template <class T>
class VoxelBuffer {
 public:
  using value_type = T;
  using const_iterator = const T*;
  using iterator = const T*;

  VoxelBuffer() = default;
  // Takes the values (implicit, so `volume.voxels = std::move(values)` moves, not copies).
  VoxelBuffer(std::vector<T> owned) : owned_(std::move(owned)) { point_at_owned(); }

  // Views `count` values at `data` without copying them. `owner` keeps that memory alive for
  // as long as this buffer or any copy of it views it (e.g. a handle to a numpy array); it may
  // be null only when the memory outlives every copy by other means.
  static VoxelBuffer view(const T* data, size_t count, std::shared_ptr<const void> owner) {
    VoxelBuffer b;
    b.data_ = data;
    b.size_ = count;
    b.owner_ = std::move(owner);
    b.view_ = true;
    return b;
  }

  VoxelBuffer(const VoxelBuffer& o)
      : owned_(o.owned_), data_(o.data_), size_(o.size_), owner_(o.owner_), view_(o.view_) {
    if (!view_) point_at_owned();
  }
  VoxelBuffer(VoxelBuffer&& o) noexcept
      : owned_(std::move(o.owned_)),
        data_(o.data_),
        size_(o.size_),
        owner_(std::move(o.owner_)),
        view_(o.view_) {
    if (!view_) point_at_owned();
    o.clear();
  }
  VoxelBuffer& operator=(const VoxelBuffer& o) {
    if (this != &o) *this = VoxelBuffer(o);
    return *this;
  }
  VoxelBuffer& operator=(VoxelBuffer&& o) noexcept {
    if (this != &o) {
      owned_ = std::move(o.owned_);
      data_ = o.data_;
      size_ = o.size_;
      owner_ = std::move(o.owner_);
      view_ = o.view_;
      if (!view_) point_at_owned();
      o.clear();
    }
    return *this;
  }
  ~VoxelBuffer() = default;

  const T* data() const { return data_; }
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  const T* begin() const { return data_; }
  const T* end() const { return data_ + size_; }
  const T& operator[](size_t i) const { return data_[i]; }

  // False for a view of external memory.
  bool owns() const { return !view_; }

  // Writable values: a view is first copied into owned storage (its owner is released), so
  // writes never reach the viewed memory.
  T* mutable_data() {
    if (view_) {
      owned_.assign(data_, data_ + size_);
      owner_.reset();
      view_ = false;
      point_at_owned();
    }
    return owned_.data();
  }

  // Element-wise, whether either side owns or views.
  friend bool operator==(const VoxelBuffer& a, const VoxelBuffer& b) {
    return a.size_ == b.size_ && std::equal(a.begin(), a.end(), b.begin());
  }

 private:
  void point_at_owned() {
    data_ = owned_.data();
    size_ = owned_.size();
  }
  void clear() {
    owned_.clear();
    owner_.reset();
    data_ = nullptr;
    size_ = 0;
    view_ = false;
  }

  std::vector<T> owned_;  // the values when owning; empty for a view
  const T* data_ = nullptr;
  size_t size_ = 0;
  std::shared_ptr<const void> owner_;  // keeps a view's memory alive; null when owning
  bool view_ = false;
};

}  // namespace imx
