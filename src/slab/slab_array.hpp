// Fixed-capacity slab arrays sorted by back depth: a ZT-buffer entry or a fragment list.
#pragma once
#include <algorithm>
#include <array>
#include <span>

#include "slab/accumulate.hpp"
#include "slab/greedy_merge.hpp"
#include "slab/over.hpp"
#include "slab/slab.hpp"

namespace imx {

// What a full array does with one slab too many (SPEC §4).
enum class Overflow {
  tail,    // fold the two deepest slabs into one by over, back depth extended
  greedy,  // fold the adjacent pair with the least merge_cost (see greedy_merge.hpp)
};

namespace detail {

// Array order: back depth, then the nearer front first.
inline bool sorts_before(const Slab& a, const Slab& b) {
  return a.t_back < b.t_back || (a.t_back == b.t_back && a.front() < b.front());
}

// The helpers take the count by value and return the new one, so the compiler can see that
// every index stays inside `slots` (the count lives next to the slots in SlabArray).
inline int insert_at(std::span<Slab> slots, int count, int pos, const Slab& s) {
  if (count >= int(slots.size()) || pos > count) return count;
  for (int k = count; k > pos; --k) slots[k] = slots[k - 1];
  slots[pos] = s;
  return count + 1;
}

inline int erase_at(std::span<Slab> slots, int count, int pos) {
  count = std::min(count, int(slots.size()));
  for (int k = pos; k + 1 < count; ++k) slots[k] = slots[k + 1];
  return count - 1;
}

inline int merge_pair(std::span<Slab> slots, int count, int i) {
  slots[i] = over(slots[i], slots[i + 1]);
  return erase_at(slots, count, i + 1);
}

// Puts s at index pos. A full array would then hold capacity + 1 slabs; the policy picks the
// adjacent pair of that longer sequence to fold, so the new slab takes part in the choice.
inline int place(std::span<Slab> slots, int count, int pos, const Slab& s, Overflow o) {
  int capacity = int(slots.size());
  if (capacity <= 0) return 0;
  if (count < capacity) return insert_at(slots, count, pos, s);
  int n = capacity + 1;
  auto at = [&](int k) { return k < pos ? slots[k] : k == pos ? s : slots[k - 1]; };
  int i = o == Overflow::tail ? n - 2 : cheapest_pair(at, n);
  if (i == pos) {
    slots[pos] = over(s, slots[pos]);
    return capacity;
  }
  if (i + 1 == pos) {
    slots[i] = over(slots[i], s);
    return capacity;
  }
  // the pair lies wholly before or after the new slab (so capacity >= 2 here); the clamp only
  // shows the compiler that j + 1 stays inside the slots
  int j = std::clamp(i < pos ? i : i - 1, 0, std::max(capacity - 2, 0));
  return insert_at(slots, merge_pair(slots, capacity, j), j < pos ? pos - 1 : pos, s);
}

inline int insert_sorted(std::span<Slab> slots, int count, const Slab& s, Overflow o) {
  int pos = count;
  while (pos > 0 && sorts_before(s, slots[pos - 1])) --pos;
  return place(slots, count, pos, s, o);
}

inline int compress(std::span<Slab> slots, int count, int target) {
  target = std::max(target, 1);
  while (count > target) {
    auto at = [&](int k) { return slots[k]; };
    count = merge_pair(slots, count, cheapest_pair(at, count));
  }
  return count;
}

}  // namespace detail

// Operations shared by SlabArray<N> and SlabList; Derived provides data(), capacity(), count.
template <class Derived>
struct SlabArrayOps {
  int size() const { return self().count; }
  bool empty() const { return self().count == 0; }
  bool full() const { return self().count >= self().capacity(); }
  Slab& operator[](int i) { return self().data()[i]; }
  const Slab& operator[](int i) const { return self().data()[i]; }
  Slab* begin() { return self().data(); }
  Slab* end() { return self().data() + self().count; }
  const Slab* begin() const { return self().data(); }
  const Slab* end() const { return self().data() + self().count; }
  std::span<const Slab> items() const { return {self().data(), size_t(self().count)}; }
  void clear() { self().count = 0; }

  // Appends a slab that sorts after every stored one (the kernel's emission order).
  void push_back(const Slab& s, Overflow o = Overflow::tail) {
    if (self().count < self().capacity())
      self().data()[self().count++] = s;  // room left: place()'s insert at the end, inline
    else
      self().count = detail::place(storage(), size(), size(), s, o);
  }
  // Inserts at the sorted position (after stored slabs of equal order).
  void insert(const Slab& s, Overflow o = Overflow::tail) {
    self().count = detail::insert_sorted(storage(), size(), s, o);
  }
  // Greedy compression down to at most `target` slabs (at least one is kept).
  void compress(int target) { self().count = detail::compress(storage(), size(), target); }
  Accumulation accumulate(float a_ert = kDefaultErtOpacity) const {
    return imx::accumulate(items(), a_ert);
  }

 private:
  std::span<Slab> storage() { return {self().data(), size_t(self().capacity())}; }
  Derived& self() { return static_cast<Derived&>(*this); }
  const Derived& self() const { return static_cast<const Derived&>(*this); }
};

// N slabs held by value: a per-pixel array in a kernel's registers or a buffer of them.
template <int N>
struct SlabArray : SlabArrayOps<SlabArray<N>> {
  static_assert(N >= 1, "a slab array holds at least one slab");
  std::array<Slab, N> slots{};
  int count = 0;

  static constexpr int capacity() { return N; }
  Slab* data() { return slots.data(); }
  const Slab* data() const { return slots.data(); }
};

// A slab array over caller-provided storage; the storage's size is the capacity.
struct SlabList : SlabArrayOps<SlabList> {
  std::span<Slab> slots;
  int count = 0;

  SlabList() = default;
  explicit SlabList(std::span<Slab> storage, int stored = 0)
      : slots(storage), count(std::clamp(stored, 0, int(storage.size()))) {}
  int capacity() const { return int(slots.size()); }
  Slab* data() { return slots.data(); }
  const Slab* data() const { return slots.data(); }
};

// Slots a kernel writes before it reads them, left uninitialized: an array of Slab would be
// zeroed (its member initializers) on every call, which per pixel and stage cost more than the
// merge it holds (zslab surface stages: half of run_deferred's own time).
template <int N>
struct SlabScratch {
  SlabScratch() {}  // NOLINT: leaves `slots` uninitialized on purpose
  union {
    Slab slots[N];
  };
  Slab* data() { return slots; }
  const Slab* data() const { return slots; }
  Slab& operator[](int i) { return slots[i]; }
  const Slab& operator[](int i) const { return slots[i]; }
  std::span<Slab> span(int count = N) { return {slots, static_cast<size_t>(count)}; }
};

// A sink that keeps nothing, for callers that need only a kernel's running composite.
struct DiscardSink {
  void push_back(const Slab&, Overflow) {}
};

}  // namespace imx
