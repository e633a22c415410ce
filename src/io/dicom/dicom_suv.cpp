#include "io/dicom/dicom_suv.hpp"

#include <cmath>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx::detail {

double suv_body_weight_factor(const DicomSuvTags& t, const std::string& what) {
  auto missing = [&](const char* tag) {
    return Error(
        fmt::format("{}: \"units\": \"suv\" needs {}, which the series lacks (or holds "
                    "an unusable value)",
                    what, tag));
  };
  if (!t.units) throw missing("Units (0054,1001)");
  if (*t.units != "BQML")
    throw Error(
        fmt::format("{}: \"units\": \"suv\" needs activity concentration (Units "
                    "(0054,1001) BQML); the series has '{}'",
                    what, *t.units));
  if (!t.weight_kg || !(*t.weight_kg > 0.0)) throw missing("PatientWeight (0010,1030)");
  if (!t.has_radiopharmaceutical)
    throw missing("RadiopharmaceuticalInformationSequence (0054,0016)");
  if (!t.total_dose_bq || !(*t.total_dose_bq > 0.0))
    throw missing("RadionuclideTotalDose (0018,1074)");
  double dose = *t.total_dose_bq;
  if (t.decay_correction.value_or("START") != "ADMIN") {
    if (!t.half_life_s || !(*t.half_life_s > 0.0))
      throw missing("RadionuclideHalfLife (0018,1075)");
    if (!t.start_time_s) throw missing("RadiopharmaceuticalStartTime (0018,1072)");
    std::optional<double> scan = t.series_time_s ? t.series_time_s : t.acquisition_time_s;
    if (!scan) throw missing("SeriesTime (0008,0031) or AcquisitionTime (0008,0032)");
    double elapsed = *scan - *t.start_time_s;
    if (elapsed < 0.0) elapsed += 24.0 * 3600.0;  // injected before midnight, scanned after
    dose *= std::exp2(-elapsed / *t.half_life_s);
  }
  return *t.weight_kg * 1000.0 / dose;
}

}  // namespace imx::detail
