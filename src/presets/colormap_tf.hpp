// A transfer function from a colour map over a value range, with a threshold and a symmetric
// (signed) form: how statistical maps are shown (docs/segmentations_overlays.md).
#pragma once
#include <optional>

#include "intermix/scene.hpp"

namespace imx {

// What a {"colormap", "range", "threshold", "symmetric", "opacity"} transfer function says.
// With s(m) = clamp((m - lo) / (hi - lo), 0, 1) for a magnitude m (the value itself, or |value|
// when symmetric), a value shows the map's colour at s and the opacity `opacity * s` (per
// unit_distance mm), and nothing (opacity 0) where m < threshold. Symmetric: a negative value v
// shows like |v|, in the map's lower half mirrored outward (cold side) for a diverging map
// (cold-hot: s runs from t = 127/255 down to 0), else in the same colours as |v|; the positive
// side of a diverging map uses its upper half (t = 128/255 up to 1).
struct ColormapTransferFunction {
  Colormap map = Colormap::grey;
  double lo = 0.0, hi = 1.0;        // lo < hi; symmetric: 0 <= lo, magnitudes
  std::optional<double> threshold;  // <= hi; symmetric: >= 0
  bool symmetric = false;
  float opacity = 1.0f;  // in [0, 1]
};

// The rule above as piecewise-linear points: one per map entry on each side (256, or 128 for a
// diverging map's half), so that evaluating them between points equals the map's own
// interpolation, and a step at the threshold: a hidden point beside the first shown one, one
// float step nearer zero at -threshold and below the first point of a one-sided map, so that
// v = threshold and v = -threshold themselves show.
// Throws imx::Error when the fields break the constraints above.
TransferFunction colormap_transfer_function(const ColormapTransferFunction& c);

}  // namespace imx
