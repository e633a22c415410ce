// ResolutionControl: the resolution of frames rendered while the user moves, chosen from the
// measured cost per pixel so that a frame takes at most the budget (10 frames per second and
// more, with room for encoding and transfer).
#pragma once
#include <algorithm>
#include <array>

namespace imx::server {

class ResolutionControl {
 public:
  // Scales of the full image's side a moving frame may use, largest first. Few and fixed, so a
  // stretch of moving frames keeps one size (and one scale's kept stage arrays stay valid).
  static constexpr std::array<double, 7> kScales{1.0, 0.75, 0.5, 0.375, 0.25, 0.1875, 0.125};

  explicit ResolutionControl(double budget_ms = 45.0) : budget_ms_(budget_ms) {}

  // Records that a frame of `pixels` took `ms`; a running mean weighted to the latest frames.
  void record(double pixels, double ms) {
    if (!(pixels > 0.0) || !(ms >= 0.0)) return;
    const double per_pixel = ms / pixels;
    ms_per_pixel_ = ms_per_pixel_ > 0.0 ? 0.6 * ms_per_pixel_ + 0.4 * per_pixel : per_pixel;
  }

  // The largest scale whose frame of a `full_pixels` image fits the budget, moving down at
  // once but up only when the larger scale fits with a margin (no flicker between two sizes).
  double pick(double full_pixels) {
    if (!(ms_per_pixel_ > 0.0)) return scale_ = 0.5;  // nothing measured yet: a safe guess
    size_t at = 0;
    while (at + 1 < kScales.size() && predicted(full_pixels, kScales[at]) > budget_ms_) ++at;
    const size_t now = index_of(scale_);
    if (at < now && predicted(full_pixels, kScales[at]) > 0.8 * budget_ms_) at = now;
    return scale_ = kScales[at];
  }

  double ms_per_pixel() const { return ms_per_pixel_; }

 private:
  double predicted(double full_pixels, double scale) const {
    return ms_per_pixel_ * full_pixels * scale * scale;
  }
  static size_t index_of(double scale) {
    size_t i = 0;
    while (i + 1 < kScales.size() && kScales[i] > scale) ++i;
    return i;
  }

  double budget_ms_;
  double ms_per_pixel_ = 0.0;
  double scale_ = 0.5;
};

}  // namespace imx::server
