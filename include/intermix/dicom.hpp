// DICOM series through GDCM: listing the image series of a folder, DICOMDIR or file, and reading
// one of them as a volume in patient coordinates (LPS, mm).
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "intermix/volume.hpp"

namespace imx {

// One image series: the slices of one SeriesInstanceUID and SeriesNumber that share an
// orientation, a size and their localizer-ness. A SeriesInstanceUID whose slices differ in those
// is split into parts (a UID under several SeriesNumbers gives a series per number).
struct DicomSeriesInfo {
  std::string id;           // "201", or "201.2" for the second part of a split series
  std::string uid;          // SeriesInstanceUID
  int number = 0;           // SeriesNumber (0 when absent)
  int part = 0;             // 1, 2, ... when the UID is split; 0 when it is not
  std::string description;  // SeriesDescription
  std::string modality;     // CT, MR, PT, ...
  int rows = 0, columns = 0;
  int slices = 0;                 // images (frames of multi-frame files count one each)
  bool localizer = false;         // ImageType says LOCALIZER (scouts, topograms)
  glm::dvec3 row_direction{0.0};  // ImageOrientationPatient, first triplet (along a row)
  glm::dvec3 column_direction{0.0};
  std::vector<std::filesystem::path> files;  // in no particular order
};

// The image series found under `source`: a folder (scanned recursively, at most 16 levels and
// 100000 files, symbolic links to folders not followed), a DICOMDIR (its folder is scanned: the
// records are not trusted, they often name paths that no longer exist) or one DICOM file. Files
// that are not DICOM images are skipped; gzip-compressed ones (.dcm.gz, NAME.gz) are read.
// Sorted by series number, then part. Files that start as DICOM but cannot be read are left out
// of the series and, when `refused` is given, listed there, one message each naming the file
// and why (read_dicom refuses such a folder). With `refused`, compressed pixel data is decoded
// too (in child processes, keeping nothing), so a file whose stream is corrupt is listed there
// as well, although it stays counted in its series. Throws imx::Error naming `source` when it
// cannot be read or holds no DICOM image.
std::vector<DicomSeriesInfo> list_dicom_series(const std::filesystem::path& source,
                                               std::vector<std::string>* refused = nullptr);

struct DicomReadOptions {
  std::string series;  // "" (the largest non-localizer series), a series id ("201", "201.2") or
                       // a SeriesInstanceUID
  std::string units;   // "" (the modality's own) or "suv" (PET: standardized uptake, body weight)
  std::optional<double> slice_spacing_mm;  // resample to this spacing along the slice stack
  int frame = 0;  // of a multi-volume series (time points, diffusion directions, echoes...)
};

struct DicomVolume {
  VolumeData volume;                     // i: columns, j: rows, k: slices in position order
  DicomSeriesInfo series;                // the series read
  std::string units;                     // "HU", "BQML", "g/ml" (SUV), ... ; "" when unknown
  std::optional<glm::dvec2> window;      // WindowCenter, WindowWidth of the first slice (in units)
  std::vector<std::string> notes;        // what the reader chose or changed, one sentence each
  int frames = 1;                        // volumes in the series, all on volume's grid
  std::vector<FrameLabel> frame_labels;  // one per frame when frames > 1, in dcm2niix's order
  std::optional<double> repetition_time_s;  // RepetitionTime: a time series' step, as dcm2niix
                                            // writes it to a 4-D NIfTI's pixdim[4]
};

// Reads one series of `source` (see list_dicom_series) as a volume (frame options.frame of a
// multi-volume series: fMRI, DWI, ASL, echoes, phases, grouped as dcm2niix groups them; only
// that frame's images are decoded and kept; a Siemens mosaic's tiles are its slices):
// - slices sorted by ImagePositionPatient along the slice normal; duplicate positions (within
//   0.01 mm) and missing slices (a gap at least 1.5 times both neighbouring gaps, or the only
//   gap of three slices) are refused;
// - a series without any ImagePositionPatient is stacked in acquisition order along the patient
//   axes, centred on the origin, as dcm2niix places it (a note says so);
// - RescaleSlope / RescaleIntercept applied per slice: float when slopes differ or are not
//   integers (or intercepts are not), else the smallest of u8, i16, u16 that holds the values;
// - gantry tilt kept exactly as a sheared index_to_world when the spacing is even;
// - uneven spacing resampled to even spacing (the smallest gap, or slice_spacing_mm, shortened
//   so that the first and last slices stay on the grid), blending acquired slices linearly;
// - MONOCHROME1 values are kept as stored (a note says low values display bright); colour
//   images are refused.
// Throws imx::Error naming the file, tag or value at fault.
DicomVolume read_dicom(const std::filesystem::path& source, const DicomReadOptions& options = {});

// Every frame of a multi-volume series (one for a 3-D series), in order, each as read_dicom gives
// it with that frame; the files are read once. The series' file list (series.files) and the
// frame labels, the same for every frame, are in the first frame's alone. For `intermix convert`.
std::vector<DicomVolume> read_dicom_frames(const std::filesystem::path& source,
                                           const DicomReadOptions& options = {});

// True for a folder, a file named DICOMDIR, a .dcm or .dcm.gz file or a file with the "DICM"
// preamble:
// the sources that read_dicom (rather than read_volume) takes.
bool is_dicom_source(const std::filesystem::path& path);

// What read_dicom(source, options) gives, without decoding its pixels: dims, placement, frame
// count and labels. The storage type depends on the values, which are not read: it says f32.
VolumeHeader read_dicom_header(const std::filesystem::path& source,
                               const DicomReadOptions& options = {});

}  // namespace imx
