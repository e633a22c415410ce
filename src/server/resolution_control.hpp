// ResolutionControl: the resolution of frames rendered while the user moves, chosen from measured
// frame times so that a frame takes at most the budget (10 frames per second and more, with room
// for encoding and transfer).
#pragma once
#include <algorithm>
#include <array>
#include <cstddef>

namespace imx::server {

class ResolutionControl {
 public:
  // Scales of the full image's side a moving frame may use, largest first. Few and fixed, so a
  // stretch of moving frames keeps one size (and one scale's kept stage arrays stay valid).
  static constexpr std::array<double, 7> kScales{1.0, 0.75, 0.5, 0.375, 0.25, 0.1875, 0.125};

  // No moving frame is smaller than this on its short side while a frame of it fits the budget:
  // below it thin structures (a vessel, a cortical bone) break into dashes.
  static constexpr double kMinShortSide = 128.0;

  explicit ResolutionControl(double budget_ms = 45.0) : budget_ms_(budget_ms) {}

  // Records that a frame at `scale` of a `full_pixels` image took `ms` (a running mean per
  // scale, weighted to the latest frames; a scale not used for kMaxAge frames is forgotten, so
  // one slow moment does not keep its scale out of reach).
  void record(double scale, double full_pixels, double ms) {
    if (!(full_pixels > 0.0) || !(ms >= 0.0)) return;
    full_pixels_ = full_pixels;
    const size_t i = index_of(scale);
    for (size_t k = 0; k < kScales.size(); ++k)
      if (k != i && ms_[k] > 0.0 && ++age_[k] > kMaxAge) ms_[k] = 0.0;
    ms_[i] = ms_[i] > 0.0 ? 0.6 * ms_[i] + 0.4 * ms : ms;
    age_[i] = 0;
  }

  // The scale of the next moving frame of a `full_pixels` image whose short side is
  // `short_side`: down at once to the largest that fits the budget when the present one does not;
  // up to the largest that fits with a margin (no flicker between two sizes around the budget);
  // never below the floor (kMinShortSide) while the floor's scale fits the budget.
  double pick(double full_pixels, double short_side) {
    if (full_pixels != full_pixels_) ms_.fill(0.0);  // another image: nothing measured applies
    full_pixels_ = full_pixels;
    size_t floor = 0;  // the smallest scale at or above the floor
    while (floor + 1 < kScales.size() && kScales[floor + 1] * short_side >= kMinShortSide) ++floor;
    if (std::none_of(ms_.begin(), ms_.end(), [](double m) { return m > 0.0; }))
      return scale_ = kScales[std::min(floor, index_of(0.5))];  // nothing measured: a safe guess
    const auto largest_within = [&](double ms) {
      size_t at = 0;
      while (at + 1 < kScales.size() && predicted(at) > ms) ++at;
      return at;
    };
    const size_t now = index_of(scale_);
    size_t at = predicted(now) > budget_ms_ ? largest_within(budget_ms_) : now;
    at = std::min(at, largest_within(0.9 * budget_ms_));
    if (at > floor && predicted(floor) <= budget_ms_) at = floor;
    return scale_ = kScales[at];
  }

  // Predicted ms of a frame at scale kScales[i]: its own measurement, else a line a + b·pixels
  // through the measured scales (frames have a fixed cost too: a line through the origin from a
  // small frame would keep the scale low), else, from one measured scale, half its time taken
  // as fixed (then the next frame measures a second point).
  double predicted(size_t i) const {
    if (ms_[i] > 0.0) return ms_[i];
    double n = 0, sp = 0, sm = 0, spp = 0, spm = 0;
    for (size_t k = 0; k < kScales.size(); ++k)
      if (ms_[k] > 0.0) {
        const double p = pixels(k);
        n += 1;
        sp += p;
        sm += ms_[k];
        spp += p * p;
        spm += p * ms_[k];
      }
    const double var = n * spp - sp * sp;
    if (n >= 2 && var > 0.0) {
      const double b = std::max((n * spm - sp * sm) / var, 0.0);
      const double a = std::max((sm - b * sp) / n, 0.0);
      return a + b * pixels(i);
    }
    return 0.5 * sm + 0.5 * sm / sp * pixels(i);  // one measured scale
  }

 private:
  double pixels(size_t i) const { return full_pixels_ * kScales[i] * kScales[i]; }
  static size_t index_of(double scale) {
    size_t i = 0;
    while (i + 1 < kScales.size() && kScales[i] > scale) ++i;
    return i;
  }

  static constexpr int kMaxAge = 24;

  double budget_ms_;
  double full_pixels_ = 0.0;
  std::array<double, kScales.size()> ms_{};  // running mean per scale, 0: not measured
  std::array<int, kScales.size()> age_{};    // frames at other scales since it was measured
  double scale_ = 0.5;
};

}  // namespace imx::server
