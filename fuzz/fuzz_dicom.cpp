// DICOM reader (GDCM): the input is one DICOM file, listed and read as a series (mosaics split
// into tiles). An input starting "IMXV" instead describes the images of a multi-volume series
// (positions and the tags that tell volumes apart, 8 bytes an image), split into volumes and
// placed as read_dicom does: the grouping logic without GDCM's parsing in the way.
#include <cstring>
#include <exception>

#include "harness.hpp"
#include "intermix/dicom.hpp"
#include "io/dicom/dicom_stack.hpp"
#include "io/dicom/dicom_volumes.hpp"

namespace {

void group_images(const uint8_t* data, size_t size) {
  using imx::detail::DicomFrame;
  std::vector<DicomFrame> images;
  for (size_t at = 4; at + 8 <= size && images.size() < 96; at += 8) {
    const uint8_t* b = data + at;
    DicomFrame f;
    f.file = "image" + std::to_string(images.size());
    f.position = glm::dvec3(0.0, 0.0, (b[0] % 16) * 1.5);
    f.row_direction = glm::dvec3(1, 0, 0);
    f.column_direction = b[0] & 0x80 ? glm::dvec3(0, 0.6, 0.8) : glm::dvec3(0, 1, 0);
    f.pixel_spacing = glm::dvec2(1.0);
    f.instance_number = b[1];
    if (b[2] != 0) f.temporal_position = b[2] % 8;
    if (b[3] != 0) f.trigger_time_ms = (b[3] % 8) * 10.0;
    if (b[4] != 255) f.b_value = (b[4] % 4) * 500.0;
    if (b[5] & 1) f.gradient = glm::dvec3((b[5] >> 1) % 3, (b[5] >> 3) % 3, (b[5] >> 5) % 3);
    if (b[6] != 0) f.echo_number = b[6] % 4;
    static const char* const kComponents[] = {"", "M", "P", "R", "I"};
    f.complex_component = kComponents[b[7] % 5];
    f.acquisition_time_s = b[1] * 0.5;
    images.push_back(f);
  }
  try {
    imx::detail::DicomVolumes v = imx::detail::split_volumes(images, "fuzz");
    for (std::vector<DicomFrame>& volume : v.volumes) {
      imx::detail::DicomStack stack =
          imx::detail::order_slices(std::move(volume), 2, 2, std::nullopt, "fuzz");
      (void)imx::detail::plan_slice_grid(stack, std::nullopt, "fuzz");
    }
    imx::fuzz::accepted("volumes");
  } catch (const std::exception& e) {
    imx::fuzz::refused(e);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  if (size >= 4 && std::memcmp(data, "IMXV", 4) == 0) {
    group_images(data, size);
    return 0;
  }
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
