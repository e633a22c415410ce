// The acquired slices of one DICOM series before they are placed on an even grid: for
// read_dicom and for tests that check the geometry against the tags.
#pragma once
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "intermix/dicom.hpp"
#include "io/dicom/dicom_header.hpp"
#include "io/dicom/dicom_pixels.hpp"
#include "io/dicom/dicom_stack.hpp"

namespace imx::detail {

// The stored values of a volume's sorted frames, one after another (rows * columns each), when
// every file was read straight from its native pixel data: rescaled only into the volume's own
// type, with no float plane between.
struct StoredSlices {
  std::shared_ptr<std::byte[]> bytes;  // null when the values are float planes instead
  StoredType type = StoredType::u16;
  std::vector<StoredRange> ranges;  // per sorted frame
};

// An uninitialised buffer for voxels.
std::shared_ptr<std::byte[]> voxel_memory(size_t bytes);

// One volume (frame) of a series as acquired.
struct AcquiredSeries {
  DicomSeriesInfo info;
  DicomStack stack;                // frames sorted along the slice normal
  std::vector<FloatPlane> values;  // per sorted frame: rescaled, rows * columns
  // An RGB series (is_rgb_image): per sorted frame, its colours (rows * columns * 3 bytes), whose
  // luminance `values` hold; empty for a greyscale series.
  std::vector<std::vector<uint8_t>> colours;
  StoredSlices stored;         // instead of values, when read with stored_values
  bool integer_valued = true;  // integer pixels, one integer slope, integer intercepts
  std::string modality, photometric, rescale_type;
  DicomSuvTags suv;  // the first file's
  std::vector<std::string> notes;
  int frames = 1;                  // volumes in the series
  std::vector<FrameLabel> labels;  // one per volume when frames > 1
};

// Finds, groups into volumes, orders, checks and decodes the series `series` of `source` (see
// DicomReadOptions): the volumes `which` (frame indices; empty: every one), each file decoded
// once and only the images of those volumes kept. Throws imx::Error for a frame out of range.
// With `stored_values`, a series whose files are all native integers keeps its stored values
// (`stored`) and no float planes; any other series is decoded into `values` as without it.
std::vector<AcquiredSeries> read_acquired_volumes(const std::filesystem::path& source,
                                                  const std::string& series, std::vector<int> which,
                                                  bool stored_values = false);

// The series' volumes and their labels without decoding a pixel.
AcquiredSeries read_series_layout(const std::filesystem::path& source, const std::string& series,
                                  int frame);

}  // namespace imx::detail
