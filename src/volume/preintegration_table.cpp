#include "volume/preintegration_table.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/parallel.hpp"
#include "intermix/error.hpp"
#include "slab/over.hpp"

namespace imx {
namespace {

// A stretch of the ramp: premultiplied (C, A) and the first two moments of its absorbed light,
// sums of a_i * x_i and a_i * x_i^2 over its pieces with x_i a position along the whole ramp.
// Positions are absolute, so that `over` composes moments without knowing where a stretch
// starts; in doubles, since the second moment is recovered by a difference of large sums.
struct Stretch {
  glm::vec4 c{0.0f};
  double moment = 0.0, moment2 = 0.0;
};

// `front` over `back`, premultiplied.
inline Stretch over(const Stretch& front, const Stretch& back) {
  float t = 1.0f - front.c.a;
  return {imx::over(front.c, back.c), front.moment + t * back.moment,
          front.moment2 + t * back.moment2};
}

// The mean and mean square of where the light of a homogeneous segment of opacity a comes from
// (0 front, 1 back): density k e^-kx / (1 - e^-k) for optical depth k = -ln(1 - a).
glm::dvec2 homogeneous_moments(float a) {
  if (a >= 1.0f) return glm::dvec2(0.0);
  double k = -std::log1p(-static_cast<double>(a));
  if (k < 1e-4) return {0.5 - k / 12.0, 1.0 / 3.0 - k / 12.0};
  const double tail = std::exp(-k) / -std::expm1(-k);  // e^-k / (1 - e^-k)
  return {1.0 / k - tail, 2.0 / (k * k) - (1.0 + 2.0 / k) * tail};
}

// w[f] = e[f] over ... over e[f+n-1] for every f, in O(e.size()) whatever n (van Herk /
// Gil-Werman: a window is the suffix of one block of n joined to the prefix of the next).
void sliding_over(const std::vector<Stretch>& e, int n, std::vector<Stretch>& prefix,
                  std::vector<Stretch>& suffix, std::vector<Stretch>& w) {
  const int len = static_cast<int>(e.size());
  for (int i = 0; i < len; ++i) prefix[i] = i % n == 0 ? e[i] : over(prefix[i - 1], e[i]);
  for (int i = len - 1; i >= 0; --i)
    suffix[i] = (i % n == n - 1 || i == len - 1) ? e[i] : over(e[i], suffix[i + 1]);
  for (int f = 0; f + n <= len; ++f)
    w[f] = f % n == 0 ? prefix[f + n - 1] : over(suffix[f], prefix[f + n - 1]);
}

}  // namespace

PreintegrationTable::PreintegrationTable(const TfLut& lut, float dt, float lo, float hi, int size,
                                         int threads)
    : size_(size), lo_(lo), hi_(hi), dt_(dt) {
  if (!(dt > 0.0f) || !std::isfinite(dt))
    throw Error(fmt::format("pre-integration: step {} mm must be positive", dt));
  if (size < 2) throw Error(fmt::format("pre-integration: table size {} is below 2", size));
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo))
    throw Error(fmt::format("pre-integration: value range [{}, {}] is empty", lo, hi));
  inv_step_ = static_cast<float>(size - 1) / (hi - lo);
  entries_.resize(static_cast<size_t>(size) * size);
  moments_.resize(entries_.size());
  const float dt0 = lut.unit_distance();
  const int bins = size - 1, m = kPiecesPerBin, pieces = bins * m;
  const double h = (static_cast<double>(hi) - lo) / bins;

  // Each piece is classified at its midpoint: straight rgb and log-transmittance per mm.
  std::vector<glm::vec3> rgb(pieces);
  std::vector<float> log_t(pieces);
  for (int p = 0; p < pieces; ++p) {
    glm::vec4 c = lut.lookup(static_cast<float>(lo + h * (p + 0.5) / m));
    rgb[p] = glm::vec3(c);
    log_t[p] = c.a >= 1.0f ? -INFINITY : std::log1p(-c.a) / dt0;  // an opaque piece stays opaque
  }

  // The diagonal is post-classification by definition (and the limit of the ramps).
  for (int i = 0; i < size; ++i) {
    glm::vec4 c = lut.lookup(value(i));
    float a = correct_opacity(c.a, dt, dt0);
    entries_[static_cast<size_t>(i) * size + i] = glm::vec4(glm::vec3(c) * a, a);
    moments_[static_cast<size_t>(i) * size + i] = glm::vec2(homogeneous_moments(a) * double{a});
  }

  // A ramp over n bins is n bin-segments of length dt/n each, every one m pieces of dt/(n m).
  parallel_for(bins, threads, [&](long begin, long end) {
    std::vector<Stretch> rising(pieces), falling(pieces), up(bins), down(bins), pre(bins),
        suf(bins), w(bins);
    // Stores window w (starting `first` bins into its ramp) as entry k: (C, A) and the moments
    // of its light along the window (0 front, 1 back), times A.
    auto store = [&](size_t k, const Stretch& w, int first, int n) {
      entries_[k] = w.c;
      const double origin = first * m, extent = n * m, a = w.c.a;
      const double m1 = (w.moment - origin * a) / extent;
      const double m2 =
          (w.moment2 - 2.0 * origin * w.moment + origin * origin * a) / (extent * extent);
      moments_[k] = glm::vec2(std::clamp(m1, 0.0, a), std::clamp(m2, 0.0, a));
    };
    for (long nn = begin; nn < end; ++nn) {
      const int n = static_cast<int>(nn) + 1;
      const float len = dt / static_cast<float>(n * m);
      for (int p = 0; p < pieces; ++p) {
        float a = -std::expm1(log_t[p] * len);
        glm::vec4 c(rgb[p] * a, a);
        const double x = p + 0.5, y = pieces - 1 - p + 0.5;
        rising[p] = {c, a * x, a * x * x};
        falling[pieces - 1 - p] = {c, a * y, a * y * y};
      }
      for (int k = 0; k < bins; ++k) {
        const Stretch* q = rising.data() + static_cast<size_t>(k) * m;
        const Stretch* r = falling.data() + static_cast<size_t>(k) * m;
        Stretch f = q[0], b = r[0];
        for (int j = 1; j < m; ++j) {
          f = over(f, q[j]);
          b = over(b, r[j]);
        }
        up[k] = f;    // scalar rising along the ray
        down[k] = b;  // scalar falling: bin bins-1-k, crossed downward
      }
      sliding_over(up, n, pre, suf, w);
      for (int f = 0; f + n <= bins; ++f) store(static_cast<size_t>(f) * size + f + n, w[f], f, n);
      sliding_over(down, n, pre, suf, w);
      for (int r = 0; r + n <= bins; ++r) {
        int f = bins - r;  // down[r] is bin f-1, crossed from value(f) toward value(f-1)
        store(static_cast<size_t>(f) * size + (f - n), w[r], r, n);
      }
    }
  });
}

}  // namespace imx
