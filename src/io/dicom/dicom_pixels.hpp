// Decoding one DICOM file's pixels through GDCM (every transfer syntax it supports) into
// rescaled values, one float plane per frame.
#pragma once
#include <vector>

#include "io/dicom/dicom_header.hpp"

namespace imx::detail {

struct DecodedFrames {
  std::vector<std::vector<float>> frames;  // rows * columns values each, x fastest
  bool integer_pixels = true;              // stored values are integers (not float pixel data)
};

// Decodes every frame of `header.file` and applies each frame's RescaleSlope and
// RescaleIntercept. Throws imx::Error naming the file when it has no pixel data, is truncated or
// cannot be decoded, is not MONOCHROME1/MONOCHROME2 with one sample per pixel, or its size
// differs from the header's.
DecodedFrames decode_dicom_frames(const DicomFileHeader& header);

}  // namespace imx::detail
