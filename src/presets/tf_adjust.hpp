// Moving and widening a transfer function along the value axis, as Slicer's shift slider does.
#pragma once
#include "intermix/scene.hpp"

namespace imx {

// Every point's value v becomes centre + scale * (v - centre) + shift: "shift" moves the whole
// function by that many data units, "scale" (> 0) stretches it about `centre` (> 1 wider ramps,
// < 1 narrower). Colours and opacities stay as they are, so the result at v' is the original at
// (v' - shift - centre) / scale + centre.
void shift_and_scale(TransferFunction& tf, double centre, double shift, double scale);

}  // namespace imx
