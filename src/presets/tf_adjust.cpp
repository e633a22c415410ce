#include "presets/tf_adjust.hpp"

namespace imx {

void shift_and_scale(TransferFunction& tf, double centre, double shift, double scale) {
  for (TfPoint& p : tf.points) p.value = centre + scale * (p.value - centre) + shift;
}

}  // namespace imx
