// KeptSlabArrays: whole-frame per-sample slab arrays kept between frames for object-level reuse
// (SPEC §4): up to `capacity` full-precision slabs and their count per sample, stored and loaded
// bit for bit, so a merge of kept arrays equals the merge of freshly computed ones.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "slab/zt_buffer.hpp"

namespace imx {

class KeptSlabArrays {
 public:
  // Left uninitialized: a frame that fills an array writes every sample of it.
  KeptSlabArrays(size_t samples, int capacity)
      : samples_(samples),
        capacity_(std::max(capacity, 1)),
        slabs_(new PackedSlab32[samples * static_cast<size_t>(capacity_)]),
        counts_(new uint8_t[samples]) {}

  // Copies the array of `sample` into `out` (room for capacity() slabs); returns its length.
  int load(size_t sample, std::span<Slab> out) const {
    const PackedSlab32* in = slabs_.get() + sample * static_cast<size_t>(capacity_);
    int n = std::min<int>(counts_[sample], static_cast<int>(out.size()));
    for (int k = 0; k < n; ++k) out[static_cast<size_t>(k)] = unpack(in[k]);
    return n;
  }

  // Stores `slabs` (at most capacity(); the rest is dropped) as the array of `sample`.
  void store(size_t sample, std::span<const Slab> slabs) {
    PackedSlab32* out = slabs_.get() + sample * static_cast<size_t>(capacity_);
    int n = std::min(capacity_, static_cast<int>(slabs.size()));
    for (int k = 0; k < n; ++k) out[k] = pack32(slabs[static_cast<size_t>(k)]);
    counts_[sample] = static_cast<uint8_t>(n);
  }

  size_t samples() const { return samples_; }
  int capacity() const { return capacity_; }
  size_t bytes() const { return bytes_for(samples_, capacity_); }
  static size_t bytes_for(size_t samples, int capacity) {
    return samples * (static_cast<size_t>(std::max(capacity, 1)) * sizeof(PackedSlab32) + 1);
  }

 private:
  size_t samples_;
  int capacity_;
  std::unique_ptr<PackedSlab32[]> slabs_;
  std::unique_ptr<uint8_t[]> counts_;
};

}  // namespace imx
