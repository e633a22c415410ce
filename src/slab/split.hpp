// In-slab visibility interpolation: splitting a slab at a depth into a front and a back part
// (SPEC §4: OVI, HVI and the beta blend of seed 002 eq. 4; back parts by inverting over).
#pragma once
#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "slab/slab.hpp"

namespace imx {

enum class Interpolation {
  ovi,    // opacity grows linearly with depth inside the slab (the default)
  hvi,    // homogeneous medium: opacity follows Beer-Lambert
  blend,  // beta * OVI + (1 - beta) * HVI
};

struct InSlabInterpolation {
  Interpolation mode = Interpolation::ovi;
  float beta = 1.0f;  // blend only: 1 is OVI, 0 is HVI; clamped to [0, 1]
};

struct SlabParts {
  Slab front;  // [slab front, split depth]
  Slab back;   // [split depth, slab back]; `front over back` gives the slab again
};

// Below this transmittance a front part hides its back part entirely: the back is left empty
// rather than divided by ~0 (one float ulp under 1 is 6e-8).
inline constexpr float kOpaqueGuard = 1e-7f;

// Opacity of the first fraction x of a homogeneous medium of opacity a: 1 - (1 - a)^x.
inline float homogeneous_opacity(float a, float x) {
  if (!(x > 0.0f)) return 0.0f;
  if (x >= 1.0f) return a;
  if (a >= 1.0f) return 1.0f;
  // expm1/log1p keep faint media accurate where 1 - (1 - a)^x would cancel
  return -std::expm1(x * std::log1p(-a));
}

// Visibility of the first fraction x in [0, 1] of a slab of visibility v.
inline glm::vec4 front_visibility(const glm::vec4& v, float x, const InSlabInterpolation& m) {
  x = std::clamp(x, 0.0f, 1.0f);
  float a = v.a;
  if (m.mode == Interpolation::ovi) return v * x;
  float h = homogeneous_opacity(a, x);
  // colour follows opacity (C_f = C A_f / A); a medium without opacity has the limit ratio x
  float h_ratio = a > 0.0f ? h / a : x;
  if (m.mode == Interpolation::hvi) return {glm::vec3(v) * h_ratio, h};
  float beta = std::clamp(m.beta, 0.0f, 1.0f);
  float ratio = beta * x + (1.0f - beta) * h_ratio;
  return {glm::vec3(v) * ratio, beta * x * a + (1.0f - beta) * h};
}

// The back part that makes `front over back` reproduce `whole`: over inverted.
inline glm::vec4 back_visibility(const glm::vec4& whole, const glm::vec4& front) {
  float transmittance = 1.0f - front.a;
  if (transmittance < kOpaqueGuard) return glm::vec4(0.0f);
  glm::vec4 back = (whole - front) / transmittance;
  // rounding only: a part of a valid slab is never negative nor more than opaque
  back = glm::max(back, glm::vec4(0.0f));
  back.a = std::min(back.a, 1.0f);
  return back;
}

namespace detail {

inline SlabParts whole_in_front(const Slab& s) {
  return {s, Slab{s.t_back, 0.0f, glm::vec4(0.0f)}};
}

inline SlabParts whole_behind(const Slab& s) {
  return {Slab{s.front(), 0.0f, glm::vec4(0.0f)}, s};
}

inline SlabParts split_fraction(const Slab& s, float x, float depth, const InSlabInterpolation& m) {
  glm::vec4 f = front_visibility(s.color, x, m);
  return {Slab::between(s.front(), depth, f),
          Slab::between(depth, s.t_back, back_visibility(s.color, f))};
}

}  // namespace detail

// Splits `s` at distance t from its front. t <= 0 leaves everything behind, t >= thickness
// everything in front; a surface (thickness 0) therefore always lands in the front part.
inline SlabParts split(const Slab& s, float t, const InSlabInterpolation& m = {}) {
  if (!(t < s.thickness)) return detail::whole_in_front(s);
  if (t <= 0.0f) return detail::whole_behind(s);
  return detail::split_fraction(s, t / s.thickness, s.front() + t, m);
}

// Splits `s` at depth z; the parts meet exactly at z (what the intermixing kernel needs).
inline SlabParts split_at_depth(const Slab& s, float z, const InSlabInterpolation& m = {}) {
  if (!(z < s.t_back)) return detail::whole_in_front(s);
  float lo = s.front();
  if (z <= lo) return detail::whole_behind(s);
  return detail::split_fraction(s, (z - lo) / s.thickness, z, m);
}

}  // namespace imx
