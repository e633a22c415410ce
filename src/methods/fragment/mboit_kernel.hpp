// Moment-based OIT kernel (after Münstermann et al. 2018) with 4 power moments. Pass 1 sums each
// contribution's absorbance -ln(1 - A) times the powers 0..4 of its warped depth. Pass 2 bounds,
// for each contribution, the absorbance in front of it from those moments, and composites the
// contributions weighted by the resulting transmittance; the sum is rescaled to the exact total
// opacity 1 - exp(-b0). Unordered, two passes, 20 bytes of moments per pixel. Pure.
#pragma once
#include <algorithm>
#include <cmath>
#include <span>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "frame/fragment_context.hpp"
#include "methods/fragment/wboit_kernel.hpp"

namespace imx {

// Opacity 1 has infinite absorbance: opaque contributions count as this opaque.
inline constexpr float kMomentMaxOpacity = 0.9999f;
// Weight of the point at the fragment's own depth added to the lower bound (between the lower
// and the upper bound of the absorbance in front of it, leaning to the lower).
inline constexpr double kMomentOverestimation = 0.25;
// Mixes the moments slightly toward those of a fixed distribution, keeping the Hankel matrix
// positive definite when the contributions sit on fewer than three depths.
inline constexpr double kMomentBias = 5e-6;

// Depth t mapped to [-1, 1], logarithmically between the scene's depth bounds.
inline double moment_depth(float t, const DepthRange& r) {
  double u = std::log(std::max(t, r.near) / r.near) / std::log(r.far / r.near);
  return std::clamp(2.0 * u - 1.0, -1.0, 1.0);
}

struct PowerMoments {
  double b0 = 0.0;             // total absorbance
  double b[4] = {0, 0, 0, 0};  // sum of absorbance * z^k, k = 1..4

  void add(float opacity, double z) {
    double a = -std::log1p(-std::min(opacity, kMomentMaxOpacity));
    b0 += a;
    double zk = 1.0;
    for (double& m : b) m += a * (zk *= z);
  }

  // Transmittance in front of depth z: exp(-b0 * F), F the fraction of absorbance before z
  // bounded by the 3-point canonical distribution through z that matches the moments.
  double transmittance_before(double z) const {
    if (!(b0 > 0.0)) return 1.0;
    constexpr double bias_target[4] = {0.0, 0.375, 0.0, 0.375};
    double m[4];
    for (int k = 0; k < 4; ++k)
      m[k] = (1.0 - kMomentBias) * (b[k] / b0) + kMomentBias * bias_target[k];
    const double b1 = m[0], b2 = m[1], b3 = m[2], b4 = m[3];
    // Cholesky factor of the Hankel matrix [[1, b1, b2], [b1, b2, b3], [b2, b3, b4]]
    constexpr double tiny = 1e-12;
    double l22 = std::sqrt(std::max(b2 - b1 * b1, tiny));
    double l32 = (b3 - b1 * b2) / l22;
    double l33 = std::sqrt(std::max(b4 - b2 * b2 - l32 * l32, tiny));
    // solve H c = (1, z, z^2): forward then backward substitution
    double y1 = 1.0;
    double y2 = (z - b1 * y1) / l22;
    double y3 = (z * z - b2 * y1 - l32 * y2) / l33;
    double c2 = y3 / l33;
    double c1 = (y2 - l32 * c2) / l22;
    double c0 = y1 - b1 * c1 - b2 * c2;
    // the other two support points are the roots of c0 + c1 x + c2 x^2
    double x1, x2;
    if (std::abs(c2) < tiny) {
      x1 = std::abs(c1) > tiny ? -c0 / c1 : 2.0;
      x2 = 2.0;  // outside [-1, 1]: carries no weight below z
    } else {
      double disc = std::sqrt(std::max(c1 * c1 - 4.0 * c0 * c2, 0.0));
      x1 = (-c1 - disc) / (2.0 * c2);
      x2 = (-c1 + disc) / (2.0 * c2);
    }
    // weights of the points {z, x1, x2} matching moments 0..2 (Lagrange basis expectations)
    auto weight = [&](double xi, double xj, double xk) {
      double den = (xi - xj) * (xi - xk);
      if (std::abs(den) < tiny) den = den < 0.0 ? -tiny : tiny;
      return (b2 - (xj + xk) * b1 + xj * xk) / den;
    };
    double w_z = weight(z, x1, x2), w1 = weight(x1, z, x2), w2 = weight(x2, z, x1);
    double lower = (x1 < z ? w1 : 0.0) + (x2 < z ? w2 : 0.0);
    double fraction = std::clamp(lower + kMomentOverestimation * w_z, 0.0, 1.0);
    return std::exp(-b0 * fraction);
  }
};

inline glm::vec4 trace_mboit(const Ray& ray, std::span<const Fragment> fragments,
                             std::span<const PreparedVolume> volumes,
                             std::span<const ShadingLight> lights, const HybridParams& hp,
                             const DepthRange& range, VolumeFilter filter = {}) {
  const RayVolumes rv(ray, volumes, hp.step, hp.iso_bisections, lights, filter);
  PowerMoments moments;
  for_each_contribution(ray, fragments, volumes, lights, hp, rv, [&](const glm::vec4& c, float t) {
    moments.add(c.a, moment_depth(t, range));
  });
  if (!(moments.b0 > 0.0)) return glm::vec4(0.0f);
  glm::dvec3 colour(0.0);
  double alpha = 0.0;
  for_each_contribution(ray, fragments, volumes, lights, hp, rv, [&](const glm::vec4& c, float t) {
    double tr = moments.transmittance_before(moment_depth(t, range));
    colour += glm::dvec3(c) * tr;
    alpha += c.a * tr;
  });
  double total = 1.0 - std::exp(-moments.b0);
  if (!(alpha > 0.0)) return {0.0f, 0.0f, 0.0f, static_cast<float>(total)};
  return {glm::vec3(colour * (total / alpha)), static_cast<float>(total)};
}

}  // namespace imx
