// Standardized uptake value by body weight for PET series.
#pragma once
#include <string>

#include "io/dicom/dicom_header.hpp"

namespace imx::detail {

// The factor from activity concentration (Bq/ml) to SUV (g/ml): weight in g over the injected
// dose decayed to the scan start (SeriesTime, else AcquisitionTime) from
// RadiopharmaceuticalStartTime; no decay when DecayCorrection is ADMIN (images are corrected to
// the injection time already). Throws imx::Error naming `what` and the first missing tag.
double suv_body_weight_factor(const DicomSuvTags& tags, const std::string& what);

}  // namespace imx::detail
