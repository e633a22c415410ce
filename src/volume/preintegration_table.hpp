// PreintegrationTable: (C, A) of a ray segment whose scalar runs linearly from s_f to s_b (SPEC
// §2).
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "volume/sample_formulas.hpp"
#include "volume/sample_ops.hpp"
#include "volume/tf_lut.hpp"

namespace imx {

// A non-owning view of a table with the pure lookup the ray marcher calls per segment.
struct PreintegrationView {
  const glm::vec4* data = nullptr;  // size x size, row = front value s_f, column = back value s_b
  // size x size beside each entry of `data`: the mean and the mean square of where its light
  // comes from along the segment, each times A (so that they interpolate with A)
  const glm::vec2* moments = nullptr;
  int size = 0;
  float lo = 0.0f;        // scalar at index 0
  float inv_step = 1.0f;  // (size - 1) / (hi - lo)

  // Premultiplied (C, A), bilinear between the entries around (s_f, s_b); values outside the
  // domain are clamped to it.
  glm::vec4 lookup(float s_f, float s_b) const {
    Cell k = cell(s_f, s_b);
    return bilinear(data + k.offset, k);
  }

  // Where along a segment (0 front, 1 back) its light comes from, weighted by the light each
  // point adds: the mean and the standard deviation of that position.
  struct Light {
    float centre = 0.5f;  // 0.5 for a transparent segment
    float spread = 0.0f;
  };

  // As lookup(), and where the segment's light comes from.
  glm::vec4 lookup(float s_f, float s_b, Light& light) const {
    Cell k = cell(s_f, s_b);
    glm::vec4 c = bilinear(data + k.offset, k);
    light = light_of(c.a, bilinear(moments + k.offset, k));
    return c;
  }

  static Light light_of(float a, glm::vec2 moments) {
    Light light;
    sample_formulas::light_of<ScalarOps>(a, moments.x, moments.y, light.centre, light.spread);
    return light;
  }

 private:
  struct Cell {
    size_t offset;  // of the entry at the lower corner
    float fx, fy;   // position between that entry and the next, per axis
  };
  Cell cell(float s_f, float s_b) const {
    float x = axis(s_f), y = axis(s_b);
    int i = std::min(static_cast<int>(x), size - 2), j = std::min(static_cast<int>(y), size - 2);
    return {static_cast<size_t>(i) * size + j, x - static_cast<float>(i),
            y - static_cast<float>(j)};
  }
  template <class T>
  T bilinear(const T* r0, const Cell& k) const {
    const T* r1 = r0 + size;
    T a = r0[0] + k.fy * (r0[1] - r0[0]);
    T b = r1[0] + k.fy * (r1[1] - r1[0]);
    return a + k.fx * (b - a);
  }
  float axis(float s) const {
    float x = (s - lo) * inv_step;
    return x > 0.0f ? std::min(x, static_cast<float>(size - 1)) : 0.0f;  // NaN goes to 0
  }
};

// Entry (f, b) holds the emission-absorption integral over a segment of length dt (mm) along
// which the scalar goes linearly from value(f) to value(b), with extinction
// tau(s) = -ln(1 - a(s)) / dt0 from the LUT's alpha per unit_distance dt0, and colour the LUT's
// straight rgb: C = integral of rgb * tau * transmittance, A = 1 - exp(-integral of tau). The
// colour is unshaded emission: the marcher scales it by Blinn-Phong along the segment.
// The diagonal is exactly post-classification: A = 1 - (1 - a)^(dt/dt0), C = rgb * A.
// Beside each entry the table keeps the first two moments of where along the segment its light
// comes from (each point weighted by the light it adds, its opacity times the transmittance in
// front of it), so that a marcher can shade where the light comes from: near the back of a ramp
// that enters a medium, near the front of an opaque one, spread out in a thin one.
class PreintegrationTable {
 public:
  static constexpr int kDefaultSize = 256;
  // Sub-segments per table bin: enough that each LUT entry is crossed by at least one midpoint
  // for a 256-entry table over the TF's own range (4096 / 255 ~ 16 entries per bin).
  static constexpr int kPiecesPerBin = 32;

  PreintegrationTable() = default;
  // Over the TF's value range [lut.lo(), lut.hi()].
  PreintegrationTable(const TfLut& lut, float dt)
      : PreintegrationTable(lut, dt, lut.lo(), lut.hi()) {}
  // Over [lo, hi]: pass the union of the TF and data ranges so that ramps reaching beyond the TF
  // points integrate the constant ends instead of being clamped. Parallel on up to `threads`
  // threads (0 = all). Throws imx::Error for dt <= 0, size < 2 or an empty or non-finite range.
  PreintegrationTable(const TfLut& lut, float dt, float lo, float hi, int size = kDefaultSize,
                      int threads = 0);

  PreintegrationView view() const {
    return {entries_.data(), moments_.data(), size_, lo_, inv_step_};
  }
  glm::vec4 lookup(float s_f, float s_b) const { return view().lookup(s_f, s_b); }
  glm::vec4 entry(int f, int b) const { return entries_[static_cast<size_t>(f) * size_ + b]; }
  // Where entry (f, b)'s light comes from along the segment, 0 at the front, 1 at the back.
  PreintegrationView::Light light(int f, int b) const {
    size_t k = static_cast<size_t>(f) * size_ + b;
    return PreintegrationView::light_of(entries_[k].a, moments_[k]);
  }
  // The scalar value of table index i.
  float value(int i) const { return lo_ + (hi_ - lo_) * static_cast<float>(i) / (size_ - 1); }

  int size() const { return size_; }
  size_t bytes() const {
    return entries_.capacity() * sizeof(glm::vec4) + moments_.capacity() * sizeof(glm::vec2);
  }
  float dt() const { return dt_; }
  float lo() const { return lo_; }
  float hi() const { return hi_; }

 private:
  std::vector<glm::vec4> entries_;
  std::vector<glm::vec2> moments_;  // PreintegrationView::moments
  int size_ = 0;
  float lo_ = 0.0f, hi_ = 1.0f, inv_step_ = 1.0f;
  float dt_ = 0.0f;
};

}  // namespace imx
