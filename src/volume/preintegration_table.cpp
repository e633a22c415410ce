#include "volume/preintegration_table.hpp"

#include <cmath>

#include <fmt/format.h>

#include "core/parallel.hpp"
#include "intermix/error.hpp"

namespace imx {
namespace {

// `front` over `back`, premultiplied.
inline glm::vec4 over(const glm::vec4& front, const glm::vec4& back) {
  return front + (1.0f - front.a) * back;
}

// w[f] = e[f] over ... over e[f+n-1] for every f, in O(e.size()) whatever n (van Herk /
// Gil-Werman: a window is the suffix of one block of n joined to the prefix of the next).
void sliding_over(const std::vector<glm::vec4>& e, int n, std::vector<glm::vec4>& prefix,
                  std::vector<glm::vec4>& suffix, std::vector<glm::vec4>& w) {
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
  }

  // A ramp over n bins is n bin-segments of length dt/n each, every one m pieces of dt/(n m).
  parallel_for(bins, threads, [&](long begin, long end) {
    std::vector<glm::vec4> piece(pieces), up(bins), down(bins), pre(bins), suf(bins), w(bins);
    for (long nn = begin; nn < end; ++nn) {
      const int n = static_cast<int>(nn) + 1;
      const float len = dt / static_cast<float>(n * m);
      for (int p = 0; p < pieces; ++p) {
        float a = -std::expm1(log_t[p] * len);
        piece[p] = glm::vec4(rgb[p] * a, a);
      }
      for (int k = 0; k < bins; ++k) {
        const glm::vec4* q = piece.data() + static_cast<size_t>(k) * m;
        glm::vec4 f = q[0], b = q[m - 1];
        for (int j = 1; j < m; ++j) {
          f = over(f, q[j]);
          b = over(b, q[m - 1 - j]);
        }
        up[k] = f;               // scalar rising along the ray
        down[bins - 1 - k] = b;  // scalar falling: bins in reverse order
      }
      sliding_over(up, n, pre, suf, w);
      for (int f = 0; f + n <= bins; ++f) entries_[static_cast<size_t>(f) * size + f + n] = w[f];
      sliding_over(down, n, pre, suf, w);
      for (int r = 0; r + n <= bins; ++r) {
        int f = bins - r;  // down[r] is bin f-1, crossed from value(f) toward value(f-1)
        entries_[static_cast<size_t>(f) * size + (f - n)] = w[r];
      }
    }
  });
}

}  // namespace imx
