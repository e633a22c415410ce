// Diffusion-weighted NRRD (Slicer's and teem's DWMRI keys) as frame labels: b-value and gradient.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "intermix/volume.hpp"

namespace imx::detail {

// The labels of the `frames` frames of a NRRD whose key/value pairs (`keys`, key -> value) say
// "modality:=DWMRI": one per frame, with b_value, b_vector and text; empty when they do not.
// The keys, as Slicer writes them: DWMRI_b-value (the largest b-value), DWMRI_gradient_NNNN
// (one per frame, 4 digits from 0000) and DWMRI_NEX_NNNN (gradient NNNN stands for that many
// frames, NNNN onwards). A frame's b-value is DWMRI_b-value times its gradient's squared length
// over the longest one's, as Slicer scales it, and b_vector is the gradient made unit length
// (zero where the gradient is). Throws imx::Error naming `what` and the key when a frame has no
// gradient, there are more gradients than frames, or a value is not a number.
std::vector<FrameLabel> dwmri_frame_labels(const std::map<std::string, std::string>& keys,
                                           int frames, const std::string& what);

}  // namespace imx::detail
