// k+-buffer (SPEC §6): at most k fragments per pixel stored in arrival order, the rest mixed
// into a tail; optionally merging overlapping fragments whole by OFM as they arrive.
#pragma once
#include <algorithm>
#include <array>
#include <span>

#include <glm/vec4.hpp>

#include "slab/ofm.hpp"
#include "slab/over.hpp"
#include "slab/slab.hpp"

namespace imx {

inline constexpr int kMaxKBufferSize = 64;

struct KPlusSettings {
  int k = 8;           // stored fragments per pixel, 1 .. kMaxKBufferSize
  bool merge = false;  // OFM: an arriving fragment first merges into the stored ones it overlaps
};

// One pixel's buffer. Slots are kept sorted by back depth (the "max array": the deepest is the
// last), so the resolve pass needs no sort. Pure: fixed storage, no allocation.
class KPlusBuffer {
 public:
  explicit KPlusBuffer(const KPlusSettings& s)
      : k_(std::clamp(s.k, 1, kMaxKBufferSize)), merge_(s.merge) {}

  // The store pass for one fragment, in arrival order.
  void insert(const Slab& s) {
    MergedFragment f = MergedFragment::from(s);
    if (merge_) {
      // stored fragments are disjoint and sorted, so the ones f overlaps form one run; merging
      // can widen f, so look again until nothing more overlaps
      for (bool again = true; again;) {
        again = false;
        for (int i = 0; i < count_; ++i)
          if (overlaps(slots_[i].slab, f.slab)) {
            f = ofm_merge(slots_[i], f);
            erase(i--);
            again = true;
          }
      }
    }
    if (count_ < k_) {
      place(f);
    } else if (before(f.slab, slots_[count_ - 1].slab)) {
      to_tail(slots_[--count_]);  // evict the deepest
      place(f);
    } else {
      to_tail(f);
    }
  }

  int size() const { return count_; }
  bool has_tail() const { return has_tail_; }
  std::span<const MergedFragment> stored() const { return {slots_.data(), size_t(count_)}; }
  const MergedFragment& tail() const { return tail_; }

  // The resolve pass: stored fragments front to back, then the tail (behind all of them).
  // Writes at most k + 1 slabs to `out` and returns how many.
  int resolve(std::span<Slab> out) const {
    int n = 0;
    for (int i = 0; i < count_ && n < int(out.size()); ++i) out[n++] = slots_[i].slab;
    if (has_tail_ && n < int(out.size())) out[n++] = tail_.slab;
    return n;
  }

  glm::vec4 composite() const {
    glm::vec4 c(0.0f);
    for (int i = 0; i < count_; ++i) c = over(c, slots_[i].slab.color);
    return has_tail_ ? over(c, tail_.slab.color) : c;
  }

  // Bytes one pixel's buffer takes on a GPU: k fragments and the tail, each back depth and
  // RGBA as f32, plus thickness and A_sum when merging.
  static constexpr int bytes_per_pixel(int k, bool merge) { return (k + 1) * (merge ? 28 : 20); }

 private:
  static bool before(const Slab& a, const Slab& b) {
    return a.t_back < b.t_back || (a.t_back == b.t_back && a.front() < b.front());
  }

  // Sorted insertion after slabs of equal order, so equal depths keep arrival order.
  void place(const MergedFragment& f) {
    int pos = count_;
    while (pos > 0 && before(f.slab, slots_[pos - 1].slab)) --pos;
    for (int i = count_; i > pos; --i) slots_[i] = slots_[i - 1];
    slots_[pos] = f;
    ++count_;
  }

  void erase(int i) {
    for (int j = i; j + 1 < count_; ++j) slots_[j] = slots_[j + 1];
    --count_;
  }

  // The store pass has no order, so the tail mixes (M1, order-independent) rather than over.
  void to_tail(const MergedFragment& f) {
    tail_ = has_tail_ ? ofm_merge(tail_, f) : f;
    has_tail_ = true;
  }

  std::array<MergedFragment, kMaxKBufferSize> slots_{};
  int count_ = 0;
  int k_;
  bool merge_;
  MergedFragment tail_{};
  bool has_tail_ = false;
};

}  // namespace imx
