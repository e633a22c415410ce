// The acquired slices of one DICOM series before they are placed on an even grid: for
// read_dicom and for tests that check the geometry against the tags.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "intermix/dicom.hpp"
#include "io/dicom/dicom_header.hpp"
#include "io/dicom/dicom_pixels.hpp"
#include "io/dicom/dicom_stack.hpp"

namespace imx::detail {

struct AcquiredSeries {
  DicomSeriesInfo info;
  DicomStack stack;                        // frames sorted along the slice normal
  std::vector<FloatPlane> values;  // per sorted frame: rescaled, rows * columns
  bool integer_valued = true;              // integer pixels, one integer slope, integer intercepts
  std::string modality, photometric, rescale_type;
  DicomSuvTags suv;  // the first file's
  std::vector<std::string> notes;
};

// Finds, orders, checks and decodes the series `series` of `source` (see DicomReadOptions).
AcquiredSeries read_acquired_series(const std::filesystem::path& source, const std::string& series);

}  // namespace imx::detail
