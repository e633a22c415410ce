// VolumeMarcher: one volume's part of a ray as a stream of slabs (SPEC §2, §4), the source of
// volume contributions for every method but the reference. Pure: no allocation, no exceptions.
#pragma once
#include <algorithm>
#include <cmath>
#include <span>
#include <type_traits>

#include <glm/glm.hpp>

#include "core/blinn_phong.hpp"
#include "core/ray.hpp"
#include "slab/over.hpp"
#include "slab/slab.hpp"
#include "volume/brick_dda.hpp"
#include "volume/kept_span.hpp"
#include "volume/label_classifier.hpp"
#include "volume/prepared_volume.hpp"
#include "volume/ray_shading.hpp"

namespace imx {

// Cuts [t0, t1] at the points k * step (anchored at t = 0, so the slabs of several volumes
// align), and emits each piece as the slab {t_back, length, (C, A)}: pre-integrated between the
// values at its ends (opacity-corrected for pieces shorter than the step at the span's ends) or
// post-classified at the mean of the two, then Blinn-Phong shaded at its midpoint. Pieces that
// lie wholly in bricks the TF makes empty are skipped without sampling, with a 3D DDA over the
// bricks and, in distance mode, jumps over the empty bricks ahead. Empty slabs are not emitted;
// the caller applies early ray termination by no longer asking.
//
// With SlabExtent::visible (the default; pre-integration only), each slab is trimmed to the part
// of its piece where the linear scalar ramp has non-zero TF opacity, centred on where its light
// comes from: the same visibility, but a depth extent that tells slab methods where within a step
// a medium begins and absorbs (e.g. where two opaque volumes meet). It is also shaded where its
// light comes from, not at the midpoint: at the table's opacity-weighted centre, or at two points
// a standard deviation either side of it when the light is spread. SlabExtent::grid keeps whole
// pieces shaded at their midpoints, as a conventional ray caster does.
enum class SlabExtent { grid, visible };

// SlabExtent::visible: narrows [front, back] to the visible part of the ramp s_f -> s_b, and within
// it to the interval centred on the light's centre `centre` (a fraction of the piece): the extent
// over which an even spread of the slab's opacity has the true first moment, so that splitting it
// linearly (OVI) puts its opacity where the medium absorbs. Keeps at least 1/16 of the piece
// so that the slab stays a medium, not a surface.
inline void trim_to_light(const TfEmptiness& tf, float s_f, float s_b, float centre, double& front,
                          double& back) {
  glm::vec2 u = tf.visible_part(s_f, s_b);
  float c = std::clamp(centre, u.x, u.y);
  float half = std::min(c - u.x, u.y - c);
  u = glm::vec2(c - half, c + half);
  constexpr float kMin = 1.0f / 16.0f;
  if (u.y - u.x < kMin) {
    float mid = std::clamp(0.5f * (u.x + u.y), 0.5f * kMin, 1.0f - 0.5f * kMin);
    u = glm::vec2(mid - 0.5f * kMin, mid + 0.5f * kMin);
  }
  double len = back - front;
  back = front + u.y * len;
  front = front + u.x * len;
}

// The cell k of the sampling grid [k, k+1) * step that holds t, guarding against rounding at its
// ends. Every marcher cuts its steps on this grid.
inline double grid_cell(double t, double step) {
  double cell = std::floor(t / step);
  while ((cell + 1.0) * step <= t) cell += 1.0;
  return cell;
}

class VolumeMarcher {
 public:
  VolumeMarcher() = default;
  // The members are built in place: assigning a freshly built BrickDda and RayShading made
  // the constructor cost about 3% of an MDVR frame (perf, ct-head).
  VolumeMarcher(const PreparedVolume& v, const Ray& ray, float t0, float t1, float step,
                std::span<const ShadingLight> lights, SlabExtent extent = SlabExtent::visible)
      : v_(&v),
        shading_(v.object->shading.enabled
                     ? RayShading(v.object->shading, v.specular, lights, -ray.dir)
                     : RayShading()),
        origin_(v.to_index(ray.origin)),
        dir_(glm::mat3(v.world_to_index) * ray.dir),
        step_(step),
        t_(t0),
        t1_(t1),
        end_(t1),
        preint_(v.accel.preint ? v.accel.preint->view() : PreintegrationView()),
        dda_(v.accel.occupancy && t1 > t0
                 ? BrickDda(v.accel.occupancy->grid(), origin_, dir_, t0, t1)
                 : BrickDda()) {
    centre_ = extent == SlabExtent::visible && preint_.data;
    trim_ = centre_ && v.accel.emptiness;
    has_no_data_ = v.has_no_data;
    wide_ = v.wide_scalar;
    align_cell();
  }

  // Only the pieces of the span that clip geometry keeps, in order: the slabs of one marcher per
  // piece, one after the other. The gaps are jumped like empty space; the brick walk over the
  // whole kept extent serves every piece, as it only ever moves forward. The pieces `kept` points
  // to must outlive the marcher.
  VolumeMarcher(const PreparedVolume& v, const Ray& ray, const KeptSpan& kept, float step,
                std::span<const ShadingLight> lights, SlabExtent extent = SlabExtent::visible)
      : VolumeMarcher(v, ray, kept.empty() ? 0.0f : kept.front(), kept.empty() ? 0.0f : kept.back(),
                      step, lights, extent) {
    if (kept.size() < 2) return;
    t1_ = kept[0].t1;
    kept_ = kept;
    piece_ = 0;
  }

  // The next slab with any visibility, in depth order; false once the span is used up.
  bool next(Slab& out);

  // Composites the slabs front to back into `acc` until its opacity reaches `ert`: the whole
  // march in one call, for a ray with nothing else to interleave. The blend stays the caller's
  // code, so that a ray composited here and one whose slabs a method blends itself round alike.
  void composite(glm::vec4& acc, float ert) {
    Slab s;
    while (acc.a < ert && next(s)) acc = over(acc, s.color);
  }

  // Where the next slab will start at the earliest.
  double position() const { return t_; }

  // Label volumes: bisections that place a boundary inside a piece, to 1/64 of a step.
  static constexpr int kLabelBisections = 6;

 private:
  // next() on the voxel type resolved once per call (volume_marcher.cpp compiles it at the
  // baseline and, through run_wide_scalar, at x86-64-v3).
  bool next_on_grid(Slab& out) {
    return v_->grid.visit([&](const auto& grid) {
      if constexpr (std::is_floating_point_v<typename std::decay_t<decltype(grid)>::value_type>)
        if (has_no_data_) return next_in<true>(grid, out);
      return next_in<false>(grid, out);
    });
  }

  // The loop with the voxel type resolved once per slab, so sampling inlines. NoData: the
  // volume has NaN or inf voxels (float only), and pieces reading them are skipped.
  template <bool NoData, class Grid>
  [[gnu::always_inline]] bool next_in(const Grid& grid, Slab& out) {
    if (v_->labels.active()) {
      do {
        if (next_label_in_piece(grid, out)) return true;
      } while (next_piece());
      return false;
    }
    do {
      if (next_in_piece<NoData>(grid, out)) return true;
    } while (next_piece());
    return false;
  }

  // A label volume's pieces, classified by the winning label (label_classifier.hpp) at the grid
  // points, each read once as in the scalar march. Where the two ends of a piece differ, the
  // boundary is found by bisection and the piece splits there into a slab of each end's label
  // (the second kept for the next call), so that a boundary lies where the indicators cross, not
  // at a grid point: no staircase of steps on an opaque label's surface. Each slab has its label's
  // opacity per unit distance (post-classification: pre-integration does not apply, as the winner
  // is not a function of one interpolated value) and is shaded at its midpoint with the gradient
  // of its label's indicator.
  template <class Grid>
  bool next_label_in_piece(const Grid& grid, Slab& out) {
    if (pending_.a > 0.0f) {
      out = Slab::between(pending_front_, pending_back_, pending_);
      pending_ = glm::vec4(0.0f);
      return true;
    }
    const bool nearest = v_->labels.nearest();
    while (t_ < t1_) {
      const double back = std::min<double>(t1_, (cell_ + 1.0) * step_);
      if (v_->accel.occupancy && t_ >= occupied_until_ && skip_empty(back)) continue;
      const double front = t_;
      const int32_t l_f =
          have_front_ ? label_front_ : winning_label(grid, index_at(front), nearest);
      const int32_t l_b = winning_label(grid, index_at(back), nearest);
      t_ = back;
      cell_ += 1.0;
      label_front_ = l_b;
      have_front_ = true;
      double cut = back;
      if (l_f != l_b) {
        double lo = front, hi = back;
        for (int i = 0; i < kLabelBisections; ++i) {
          const double m = 0.5 * (lo + hi);
          (winning_label(grid, index_at(m), nearest) == l_f ? lo : hi) = m;
        }
        cut = 0.5 * (lo + hi);
      }
      glm::vec4 first = label_slab(grid, l_f, front, cut);
      glm::vec4 second = cut < back ? label_slab(grid, l_b, cut, back) : glm::vec4(0.0f);
      if (first.a > 0.0f) {
        out = Slab::between(static_cast<float>(front), static_cast<float>(cut), first);
        pending_ = second;
        pending_front_ = static_cast<float>(cut);
        pending_back_ = static_cast<float>(back);
        return true;
      }
      if (second.a > 0.0f) {
        out = Slab::between(static_cast<float>(cut), static_cast<float>(back), second);
        return true;
      }
    }
    return false;
  }

  // Premultiplied (C, A) of label `label` over [front, back]; zero when hidden.
  template <class Grid>
  glm::vec4 label_slab(const Grid& grid, int32_t label, double front, double back) const {
    const glm::vec4 look = v_->labels.look(label);
    if (look.a <= 0.0f || !(back > front)) return glm::vec4(0.0f);
    const float a =
        correct_opacity(look.a, static_cast<float>(back - front), v_->labels.unit_distance());
    const glm::vec4 c(glm::vec3(look) * a, a);
    if (!v_->object->shading.enabled) return c;
    const glm::vec3 g = label_gradient(grid, index_at(0.5 * (front + back)), label);
    return shading_.apply(c, v_->gradient_to_world * g);
  }

  // Moves to the next kept piece, where a marcher of its own would start, or further in when a
  // jump over empty bricks already went past its start (pieces it went past are done).
  bool next_piece() {
    while (piece_ + 1 < kept_.size()) {
      const RayInterval p = kept_[++piece_];
      if (!(p.t1 > t_)) continue;
      t_ = std::max<double>(t_, p.t0);
      t1_ = p.t1;
      align_cell();
      have_front_ = false;
      return true;
    }
    return false;
  }

  template <bool NoData, class Grid>
  [[gnu::always_inline]] bool next_in_piece(const Grid& grid, Slab& out) {
    while (t_ < t1_) {
      double back = std::min<double>(t1_, (cell_ + 1.0) * step_);
      if (v_->accel.occupancy && t_ >= occupied_until_ && skip_empty(back)) continue;

      float s_f = have_front_ ? s_front_ : grid.sample(index_at(t_));
      float s_b = grid.sample(index_at(back));
      double front = t_;
      t_ = back;
      cell_ += 1.0;
      s_front_ = s_b;
      have_front_ = true;
      // A piece with no data at an end is transparent.
      if constexpr (NoData)
        if (no_data(s_f) || no_data(s_b)) continue;
      // Inside occupied bricks most pieces are still transparent: the O(1) range test spares
      // them the table lookup (the same test that empties bricks).
      if (v_->accel.emptiness && v_->accel.emptiness->is_empty_between(s_f, s_b)) continue;
      PreintegrationView::Light light;
      glm::vec4 c = classify(s_f, s_b, static_cast<float>(back - front), light);
      if (c.a <= 0.0f) continue;
      // A colour volume: the TF gave the opacity; the colour is the voxels' where the light is.
      if (v_->colours.active())
        c = glm::vec4(v_->colours.sample(index_at(front + light.centre * (back - front))) * c.a,
                      c.a);
      if (v_->object->shading.enabled)
        c = wide_ ? shade_wide(c, front, back, light) : shade(c, front, back, light);
      if (trim_) trim(s_f, s_b, light.centre, front, back);
      out = Slab::between(static_cast<float>(front), static_cast<float>(back), c);
      return true;
    }
    return false;
  }

  void align_cell() { cell_ = grid_cell(t_, step_); }

  glm::vec3 index_at(double t) const { return origin_ + static_cast<float>(t) * dir_; }

  // When the piece [t_, back] lies in empty bricks only, moves t_ past it and past every
  // further piece wholly inside the same run of empty bricks, and returns true.
  bool skip_empty(double back) {
    while (!dda_.done() && dda_.t_exit() <= t_) dda_.next();
    if (dda_.done()) return false;
    if (v_->accel.occupancy->occupied(dda_.brick())) {
      occupied_until_ = dda_.t_exit();  // no need to look again before the ray leaves it
      return false;
    }
    while (!dda_.done()) {
      int d = v_->accel.occupancy->distance(dda_.brick(), dda_.octant());
      if (d == 0) break;
      if (v_->accel.skip == SkipMode::distance)
        dda_.skip(d);
      else
        dda_.next();
    }
    double resume = dda_.done() ? end_ : dda_.t_enter();  // done: empty to the end
    if (resume < back) return false;
    t_ = std::max(back, std::floor(resume / step_) * step_);
    align_cell();
    have_front_ = false;
    return true;
  }

  void trim(float s_f, float s_b, float centre, double& front, double& back) const {
    trim_to_light(*v_->accel.emptiness, s_f, s_b, centre, front, back);
  }

  // (C, A) of the piece; for visible slabs also where its light comes from (else `light` is
  // kept: the midpoint).
  glm::vec4 classify(float s_f, float s_b, float len, PreintegrationView::Light& light) const {
    if (preint_.data) {
      glm::vec4 c = centre_ ? preint_.lookup(s_f, s_b, light) : preint_.lookup(s_f, s_b);
      if (len >= 0.9999f * step_ || c.a <= 0.0f) return c;
      // A piece shorter than the table's step: the same medium over less distance.
      return c * (correct_opacity(c.a, len, step_) / c.a);
    }
    glm::vec4 tf = v_->lut.lookup(0.5f * (s_f + s_b));
    float a = correct_opacity(tf.a, len, v_->lut.unit_distance());
    return glm::vec4(glm::vec3(tf) * a, a);
  }

  // Blinn-Phong over the piece [front, back] whose light comes from around `light`: at that one
  // point when the light is concentrated, else the mean of two points a standard deviation
  // either side of its centre: the two-point quadrature over the light's distribution, exact for
  // shading that varies quadratically along the piece, as where the normal turns within it (while
  // both points lie in the piece; one past an end is clamped to it).
  glm::vec4 shade(const glm::vec4& c, double front, double back,
                  PreintegrationView::Light light) const {
    const double len = back - front;
    if (light.spread < kMinSpread) return shade_at(c, front + light.centre * len);
    const double a = std::max(0.0f, light.centre - light.spread);
    const double b = std::min(1.0f, light.centre + light.spread);
    return 0.5f * (shade_at(c, front + a * len) + shade_at(c, front + b * len));
  }
  static constexpr float kMinSpread = 1.0f / 64.0f;  // of a piece: one point is as good
  // shade() compiled at x86-64-v3 (volume_marcher.cpp): GCC leaves it out of line in next()'s
  // wide copy, where it would run at the baseline (zSlab on FLAIR: 173 -> 168 ms, v3 159).
  glm::vec4 shade_wide(const glm::vec4& c, double front, double back,
                       PreintegrationView::Light light) const;

  glm::vec4 shade_at(const glm::vec4& c, double t) const {
    glm::vec3 p = index_at(t);
    glm::vec3 g = v_->accel.gradients ? v_->accel.gradients->sample(p) : v_->march_gradient(p);
    return shading_.apply(c, v_->gradient_to_world * g);
  }

  const PreparedVolume* v_ = nullptr;
  RayShading shading_;
  glm::vec3 origin_{0.0f}, dir_{0.0f};  // the ray in index space, same parameter t
  float step_ = 1.0f;
  double t_ = 0.0;
  double cell_ = 0.0;                  // index k of the grid cell [k, k+1) * step holding t_
  double occupied_until_ = -INFINITY;  // the ray is in an occupied brick up to here
  float t1_ = 0.0f;                    // the end of the piece being marched
  float end_ = 0.0f;                   // the end of the last piece
  PreintegrationView preint_;
  BrickDda dda_;
  float s_front_ = 0.0f;
  bool have_front_ = false;
  bool centre_ = false;       // shade visible slabs at their light's centre (needs the table)
  bool trim_ = false;         // trim them to the visible ramp (needs the emptiness table too)
  bool has_no_data_ = false;  // the volume has NaN or inf voxels: pieces reading them are skipped
  bool wide_ = false;         // march with the x86-64-v3 copy (PreparedVolume::wide_scalar)
  KeptSpan kept_;             // with two or more pieces: the pieces, t1_ ends piece_
  int32_t label_front_ = 0;   // label volumes: the winner at t_ (when have_front_)
  glm::vec4 pending_{0.0f};   // label volumes: the second slab of a split piece, when a > 0
  float pending_front_ = 0.0f, pending_back_ = 0.0f;
  int piece_ = 0;
};

}  // namespace imx
