// Slab intermixing kernel: merges two depth-sorted disjoint slab sequences in one scan (SPEC §4).
#pragma once
#include <cstddef>
#include <span>

#include <glm/vec4.hpp>

#include "slab/accumulate.hpp"
#include "slab/mix.hpp"
#include "slab/over.hpp"
#include "slab/slab.hpp"
#include "slab/slab_array.hpp"
#include "slab/split.hpp"

namespace imx {

struct IntermixSettings {
  InSlabInterpolation interpolation{};
  float a_ert = kDefaultErtOpacity;    // stop once the emitted slabs reach this opacity; 1: never
  Overflow overflow = Overflow::tail;  // what the sink does when it is full
  bool skip_empty = true;              // slabs without any visibility take no slot
};

struct IntermixResult {
  glm::vec4 accumulated{0.0f};  // front-to-back composite of everything emitted
  bool terminated = false;      // ERT fired; the rest of both sequences was dropped
};

// Streaming form, so a ray caster can feed its samples on the fly (hybrid pipeline): P is the
// stored array, the slabs of Q arrive one by one through push(), then finish() flushes.
// Sink: push_back(const Slab&, Overflow) appending in depth order (SlabArray, SlabList).
// Each step consumes the pending slab that ends first and emits one slab, so the output never
// holds more slabs than both inputs together. P and Q are each sorted and disjoint; the sink
// must not alias P.
template <class Sink>
class Intermixer {
 public:
  Intermixer(std::span<const Slab> stored, Sink& out, const IntermixSettings& settings = {})
      : stored_(stored), out_(out), settings_(settings) {}

  // Feeds the next slab of Q; false once ERT has fired, so the caller can stop marching.
  bool push(const Slab& q) {
    if (done_ || (settings_.skip_empty && q.is_empty())) return !done_;
    Slab pending = q;
    bool have_q = true;
    while (have_q && !done_) {
      if (!have_p_ && !load_p()) {
        emit(pending);  // nothing of P is left to meet it
        break;
      }
      step(p_, have_p_, pending, have_q);
    }
    return !done_;
  }

  // Emits what is left of P; call once, after the last push.
  void finish() {
    while (!done_ && (have_p_ || load_p())) {
      have_p_ = false;
      emit(p_);
    }
  }

  bool terminated() const { return done_; }
  const glm::vec4& accumulated() const { return acc_; }

 private:
  bool load_p() {
    while (next_ < stored_.size()) {
      const Slab& s = stored_[next_++];
      if (settings_.skip_empty && s.is_empty()) continue;
      p_ = s;
      have_p_ = true;
      return true;
    }
    return false;
  }

  void emit(const Slab& s) {
    if (settings_.skip_empty && s.is_empty()) return;
    out_.push_back(s, settings_.overflow);
    acc_ = over(acc_, s.color);
    done_ = ert_reached(acc_.a, settings_.a_ert);
  }

  // `b`, cut at depth `cut`, keeps `rest` as its pending remainder, unless nothing is left.
  void keep_remainder(Slab& b, bool& have_b, const Slab& rest, float cut) const {
    if (!(b.t_back > cut) || (settings_.skip_empty && rest.is_empty()))
      have_b = false;
    else
      b = rest;
  }

  // One step on the pending slabs of P and Q. `a` is the one whose back comes first (on equal
  // backs the thicker one, so a surface on a slab's back stays a slab of its own): it is
  // consumed. `b` keeps what lies behind a's back.
  void step(Slab& p, bool& have_p, Slab& q, bool& have_q) {
    bool p_first = p.t_back < q.t_back || (p.t_back == q.t_back && p.front() <= q.front());
    Slab& a = p_first ? p : q;
    Slab& b = p_first ? q : p;
    bool& have_a = p_first ? have_p : have_q;
    bool& have_b = p_first ? have_q : have_p;
    const InSlabInterpolation& m = settings_.interpolation;
    float a_front = a.front(), b_front = b.front();
    have_a = false;
    if (a_front == b_front && a.t_back == b.t_back) {  // aligned, coincident surfaces included
      have_b = false;
      emit(mix(a, b));
    } else if (b_front >= a.t_back) {  // disjoint (touching included)
      emit(a);
    } else if (b_front >= a_front) {  // partial overlap: [b_front, a.t_back] is shared
      SlabParts ap = split_at_depth(a, b_front, m);
      SlabParts bp = split_at_depth(b, a.t_back, m);
      glm::vec4 fused = mix(ap.back.color, bp.front.color);
      Slab integrated{a.t_back, a.thickness, over(ap.front.color, fused)};
      keep_remainder(b, have_b, bp.back, a.t_back);
      emit(integrated);
    } else {  // containment: a lies inside [b_front, b.t_back]
      SlabParts b_split = split_at_depth(b, a_front, m);
      SlabParts b_rest = split_at_depth(b_split.back, a.t_back, m);
      glm::vec4 fused = mix(a.color, b_rest.front.color);
      Slab integrated = Slab::between(b_front, a.t_back, over(b_split.front.color, fused));
      keep_remainder(b, have_b, b_rest.back, a.t_back);
      emit(integrated);
    }
  }

  std::span<const Slab> stored_;
  Sink& out_;
  IntermixSettings settings_;
  std::size_t next_ = 0;  // next slab of P to load
  Slab p_{};              // pending slab of P, possibly cut to its remainder
  bool have_p_ = false;
  glm::vec4 acc_{0.0f};
  bool done_ = false;
};

// Intermixes the whole of Q with P into `out` (appended after what `out` already holds).
template <class Sink>
IntermixResult intermix(std::span<const Slab> p, std::span<const Slab> q, Sink& out,
                        const IntermixSettings& settings = {}) {
  Intermixer<Sink> kernel(p, out, settings);
  for (const Slab& s : q)
    if (!kernel.push(s)) break;
  kernel.finish();
  return {kernel.accumulated(), kernel.terminated()};
}

}  // namespace imx
