// gzip-compressed DICOM files (.dcm.gz): GDCM reads files by name, so each is inflated into a
// private temporary folder that lives as long as the series read from it.
#pragma once
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace imx::detail {

// True for a file named .dcm.gz, .dicom.gz, .ima.gz or NAME.gz that starts with the gzip magic.
bool is_gzip_file(const std::filesystem::path& file);

class InflatedDicomFiles {
 public:
  InflatedDicomFiles() = default;
  ~InflatedDicomFiles();
  InflatedDicomFiles(const InflatedDicomFiles&) = delete;
  InflatedDicomFiles& operator=(const InflatedDicomFiles&) = delete;

  // Inflates `gz` (at most kMaxInflatedDicomBytes, checksum checked) into the temporary folder
  // and returns where. Throws imx::Error naming `gz` when it is corrupt or too large.
  std::filesystem::path add(const std::filesystem::path& gz);

  // `message` with every inflated file's temporary name replaced by its own, so that errors
  // name the file the user has.
  std::string original_names(std::string message) const;

 private:
  std::filesystem::path folder_;
  std::vector<std::pair<std::string, std::string>> names_;  // temporary, original
};

inline constexpr size_t kMaxInflatedDicomBytes = size_t{1} << 32;  // DICOM lengths are 32-bit

}  // namespace imx::detail
