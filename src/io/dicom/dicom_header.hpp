// What one DICOM file says about its images before any pixel is decoded: series, size, pixel
// format and, per frame, placement and rescale (from per-frame functional groups when present).
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace imx::detail {

// One 2D image of a file: the file itself, or one frame of a multi-frame file.
struct DicomFrame {
  std::filesystem::path file;
  int frame = 0;                            // index within the file
  std::optional<glm::dvec3> position;       // ImagePositionPatient of the first pixel's centre
  std::optional<glm::dvec3> row_direction;  // ImageOrientationPatient: along a row (columns grow)
  std::optional<glm::dvec3> column_direction;  // down a column (rows grow)
  std::optional<glm::dvec2> pixel_spacing;     // PixelSpacing as stored: between rows, columns
  double slope = 1.0, intercept = 0.0;         // RescaleSlope, RescaleIntercept
  std::optional<glm::dvec2> window;            // WindowCenter, WindowWidth (first values)

  // What tells the volumes of a multi-volume series apart (dicom_volumes.hpp); absent: not said.
  int instance_number = 0;                   // the file's InstanceNumber (0020,0013)
  std::vector<uint32_t> dimension_index;     // DimensionIndexValues (0020,9157)
  std::optional<int> temporal_position;      // TemporalPositionIdentifier / Index
  std::optional<double> trigger_time_ms;     // TriggerTime (0018,1060) or nominal trigger delay
  std::optional<double> b_value;             // s/mm^2: standard, Siemens, GE or Philips tags
  std::optional<glm::dvec3> gradient;        // diffusion gradient direction, patient LPS
  std::optional<int> echo_number;            // EchoNumbers (0018,0086)
  std::optional<double> echo_time_ms;        // EchoTime (0018,0081) or EffectiveEchoTime
  std::string complex_component;             // "M", "P", "R", "I" from ImageType or (0008,9208)
  std::optional<double> acquisition_time_s;  // seconds since midnight
  std::optional<double> repetition_time_ms;  // RepetitionTime (0018,0080)
  // An ADC, trace or isotropic image derived from diffusion-weighted ones (ImageType DERIVED with
  // ADC, TRACEW, ...; Philips diffusion direction (2001,xx04) 'I'): not a diffusion direction.
  bool derived_diffusion = false;
};

// The tags SUV by body weight needs, as found (nullopt: absent or malformed).
struct DicomSuvTags {
  std::optional<std::string> units;             // (0054,1001)
  std::optional<std::string> decay_correction;  // (0054,1102)
  std::optional<double> weight_kg;              // PatientWeight (0010,1030)
  bool has_radiopharmaceutical = false;         // (0054,0016) with an item
  std::optional<double> total_dose_bq;          // RadionuclideTotalDose (0018,1074)
  std::optional<double> half_life_s;            // RadionuclideHalfLife (0018,1075)
  std::optional<double> start_time_s;           // RadiopharmaceuticalStartTime (0018,1072)
  std::optional<double> series_time_s;          // SeriesTime (0008,0031)
  std::optional<double> acquisition_time_s;     // AcquisitionTime (0008,0032)
};

struct DicomFileHeader {
  std::filesystem::path file;
  std::string series_uid, sop_uid, description, modality, photometric, rescale_type;
  int series_number = 0;
  int instance_number = 0;
  int rows = 0, columns = 0, frame_count = 1;  // of one image (a mosaic's tile), images in file
  // As stored in the pixel data: a Siemens mosaic stores its tiles side by side in one frame.
  int stored_rows = 0, stored_columns = 0, stored_frames = 1;
  int mosaic_tiles = 0;  // images in a Siemens mosaic (0 when not one), a tile per DicomFrame
  // GE's reversed-polarity EPI (epi_pepolar, reverse): rows stored mirrored along the phase axis,
  // which dcm2niix flips back; so does the decoder.
  bool mirror_rows = false;
  // epi_pepolar alternating forward and reverse volumes: 1 odd, 2 even time points (each a series
  // of its own, as dcm2niix converts them); 0 otherwise.
  int polarity_part = 0;
  bool localizer = false;
  bool has_pixel_data = false;
  uint64_t pixel_bytes = 0;  // bytes in the file from the pixel data's value on
  // The pixel data element's value length; nullopt when undefined (the encapsulated form of
  // compressed syntaxes) or unknown (a deflated data set).
  std::optional<uint64_t> pixel_length;
  std::string transfer_syntax;  // (0002,0010)
  int bits_allocated = 0, bits_stored = 0, high_bit = 0, pixel_representation = 0;
  int samples_per_pixel = 1;
  int planar_configuration = 0;         // (0028,0006): 0 colour-by-pixel, 1 colour-by-plane
  std::optional<double> slice_spacing;  // SpacingBetweenSlices, else SliceThickness
  std::string slice_spacing_fault;      // why neither is usable where one is present, else ""
  std::vector<DicomFrame> frames;       // frame_count of them
  std::vector<std::string> notes;       // what the series' notes should say about this file
  DicomSuvTags suv;
};

// True when `file` starts like a DICOM file: the "DICM" preamble, or (old files without one) a
// first element of group 0008.
bool looks_like_dicom(const std::filesystem::path& file);

// Why the file meta group (0002) after the preamble is not well formed enough for GDCM (whose
// meta reader aborts on some malformed elements, and prints its own text for an unknown
// transfer syntax), as a clause to follow the file's name; "" when it is.
std::string file_meta_fault(const std::filesystem::path& file);

// The header of an image file; a Siemens mosaic becomes one frame per tile, placed where the
// tile lies (ImagePositionPatient names the mosaic's corner, not the first tile's). nullopt when
// the file is not DICOM or holds no image (no Rows or Columns: a DICOMDIR, a structured report).
// Throws imx::Error for a file that starts like DICOM but cannot be read (truncated, corrupt) and
// for an unusable header (a frame count out of bounds); imx::FileError for a file that cannot be
// opened (a permission), saying so. `not_image`, when given, is set to why nullopt was returned
// ("not a DICOM file (no DICM preamble)", "a DICOM file without an image: no Rows (0028,0010)").
std::optional<DicomFileHeader> read_dicom_header(const std::filesystem::path& file,
                                                 std::string* not_image = nullptr);

// The slice spacing of a file whose images cannot be placed without it (`use`: "a mosaic's
// tiles"); throws imx::Error naming the file and the unusable tag, or both tags when absent.
double required_slice_spacing(const DicomFileHeader& h, const char* use);

}  // namespace imx::detail
