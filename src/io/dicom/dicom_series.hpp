// Finding DICOM image files under a folder, DICOMDIR or file, grouping them into series, and
// choosing the series a read asks for.
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "intermix/dicom.hpp"
#include "io/dicom/dicom_gzip.hpp"
#include "io/dicom/dicom_header.hpp"

namespace imx::detail {

inline constexpr int kMaxDicomFiles = 100000;
inline constexpr int kMaxDicomDepth = 16;

struct DicomSeriesGroup {
  DicomSeriesInfo info;
  std::vector<DicomFileHeader> headers;                // of .dcm.gz files: their inflated copies'
  std::shared_ptr<const InflatedDicomFiles> inflated;  // keeps those copies; null when none
};

// `message` naming the files the user has, not the inflated copies of .dcm.gz files.
std::string original_names(const DicomSeriesGroup& group, std::string message);

// Every image series under `source`, sorted as list_dicom_series says. Files that start like
// DICOM but cannot be read are skipped, their messages added to `broken` when given; files of a
// folder that are not DICOM images (or too short to tell) are added to `not_images`;
// `first_broken_code` gets the errno of the first broken file (0 when its content is at fault).
// Throws imx::Error naming `source` when it holds no DICOM image (imx::FileError when what it
// holds could not be opened).
std::vector<DicomSeriesGroup> scan_dicom_series(const std::filesystem::path& source,
                                                std::vector<std::string>* broken = nullptr,
                                                std::vector<std::string>* not_images = nullptr,
                                                int* first_broken_code = nullptr);

// One line about a series: "201 'STD BRAIN 5MM' CT 512x512, 28 slices".
std::string describe_series(const DicomSeriesInfo& s);

// The series `choice` names (see DicomReadOptions::series), else the largest non-localizer
// series; `note` receives "loaded series ... of N series" when there was more than one.
// Throws imx::Error listing the series when the choice matches none or several.
const DicomSeriesGroup& choose_series(const std::vector<DicomSeriesGroup>& groups,
                                      const std::string& choice,
                                      const std::filesystem::path& source, std::string& note);

}  // namespace imx::detail
