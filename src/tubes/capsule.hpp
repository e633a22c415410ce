// Capsules (a segment's points within a radius): a ray's entry and exit, and the cheap tests
// that pass over most of them. Pure per-ray arithmetic, no allocation.
#pragma once
#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "core/ray.hpp"

namespace imx {

// The crossings of a ray with one capsule, the ray's origin moved near the segment.
struct CapsuleCrossings {
  float t[2];
  int count = 0;
};

// The ray o + t d (unit d) against the capsule of radius r around 0..ba: its entry and exit.
inline CapsuleCrossings capsule_crossings(const glm::vec3& o, const glm::vec3& d,
                                          const glm::vec3& ba, float r) {
  CapsuleCrossings out;
  const float baba = glm::dot(ba, ba), bard = glm::dot(ba, d), baoa = glm::dot(ba, o);
  const float rr = r * r;
  auto sphere = [&](const glm::vec3& c, float& near, float& far) {
    const glm::vec3 oc = o - c;
    const float b = glm::dot(d, oc), h = b * b - (glm::dot(oc, oc) - rr);
    if (h < 0.0f) return false;
    const float s = std::sqrt(h);
    near = -b - s, far = -b + s;
    return true;
  };
  const float a = baba - bard * bard;
  if (a > 1e-6f * baba) {
    const float b = baba * glm::dot(d, o) - baoa * bard;
    const float c = baba * glm::dot(o, o) - baoa * baoa - rr * baba;
    const float h = b * b - a * c;
    if (h < 0.0f) return out;
    const float s = std::sqrt(h), t0 = (-b - s) / a, t1 = (-b + s) / a;
    const float y0 = baoa + t0 * bard, y1 = baoa + t1 * bard;
    float near = t0, far = t1, unused;
    if (y0 < 0.0f || y0 > baba) {
      if (!sphere(y0 < 0.0f ? glm::vec3(0.0f) : ba, near, unused)) return out;
    }
    if (y1 < 0.0f || y1 > baba) {
      if (!sphere(y1 < 0.0f ? glm::vec3(0.0f) : ba, unused, far)) return out;
    }
    out.t[0] = near, out.t[1] = far, out.count = 2;
    return out;
  }
  // Along the axis (or a point): the two end spheres alone.
  float n0, f0, n1, f1;
  const bool h0 = sphere(glm::vec3(0.0f), n0, f0);
  const bool h1 = baba > 0.0f && sphere(ba, n1, f1);
  if (!h0 && !h1) return out;
  out.t[0] = h0 && h1 ? std::min(n0, n1) : (h0 ? n0 : n1);
  out.t[1] = h0 && h1 ? std::max(f0, f1) : (h0 ? f0 : f1);
  out.count = 2;
  return out;
}

inline float distance2_to_segment(const glm::vec3& x, const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 ba = b - a, xa = x - a;
  const float len2 = glm::dot(ba, ba);
  const float u = len2 > 0.0f ? std::clamp(glm::dot(xa, ba) / len2, 0.0f, 1.0f) : 0.0f;
  const glm::vec3 off = xa - u * ba;
  return glm::dot(off, off);
}

// Whether the line of `ray` passes within `bound` of the segment ab.
inline bool line_meets_capsule(const Ray& ray, const glm::vec3& a, const glm::vec3& b,
                               float bound) {
  const glm::vec3 w = ray.origin - a;
  const glm::vec3 o = w - glm::dot(w, ray.dir) * ray.dir;  // `a` seen across the ray, negated
  const glm::vec3 ba = b - a;
  const glm::vec3 pb = ba - glm::dot(ba, ray.dir) * ray.dir;
  const float pbpb = glm::dot(pb, pb);
  const float s = pbpb > 0.0f ? std::clamp(glm::dot(o, pb) / pbpb, 0.0f, 1.0f) : 0.0f;
  const glm::vec3 n = s * pb - o;
  return glm::dot(n, n) <= bound * bound;
}

}  // namespace imx
