// DICOM reader (GDCM): the input is one DICOM file, listed and read as a series.
#include <exception>

#include "harness.hpp"
#include "intermix/dicom.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  std::filesystem::path file = dir.write("in.dcm", data, size);
  try {
    (void)imx::list_dicom_series(file);
    const imx::DicomVolume d = imx::read_dicom(file);
    check_volume(d.volume);
    accepted("volume");
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
