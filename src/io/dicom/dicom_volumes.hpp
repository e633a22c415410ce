// Splitting the images of one series into the volumes of a multi-volume acquisition (fMRI time
// points, diffusion directions, echoes, cardiac phases, magnitude and phase), in dcm2niix's order.
#pragma once
#include <string>
#include <vector>

#include "intermix/volume.hpp"
#include "io/dicom/dicom_header.hpp"

namespace imx::detail {

struct DicomVolumes {
  std::vector<std::vector<DicomFrame>> volumes;  // each: one image per slice position
  std::vector<FrameLabel> labels;                // one per volume when there are several
  std::vector<std::string> notes;                // images left out, and why
};

// Splits `images` (one series: one size and orientation) into volumes that each hold one image
// at every slice position. Images at the same position are told apart by the tags that stay
// constant within a volume (temporal position, trigger time, b-value and gradient, echo number,
// complex component), then by acquisition order (DimensionIndexValues, InstanceNumber);
// volumes come in acquisition order, which is the order dcm2niix writes. One image per position
// gives one volume. Throws imx::Error naming `what` when the positions hold different numbers
// of images, so that no volume would be whole.
DicomVolumes split_volumes(std::vector<DicomFrame> images, const std::string& what);

}  // namespace imx::detail
