#include "io/dicom/dicom_gzip.hpp"

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streams/gzip.hpp"
#include "io/streams/input_file.hpp"

namespace imx::detail {

bool is_gzip_file(const std::filesystem::path& file) {
  std::string name = file.filename().string();
  for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (name.size() < 4 || name.compare(name.size() - 3, 3, ".gz") != 0) return false;
  // DICOM names: .dcm.gz, .dicom.gz, .ima.gz or no extension before .gz (not .nii.gz and such,
  // which a folder scan must not inflate to find out).
  const std::string inner = std::filesystem::path(name.substr(0, name.size() - 3)).extension();
  if (!inner.empty() && inner != ".dcm" && inner != ".dicom" && inner != ".ima") return false;
  std::ifstream in = try_open_input_stream(file);
  unsigned char magic[2] = {};
  in.read(reinterpret_cast<char*>(magic), 2);
  return in.gcount() == 2 && magic[0] == 0x1f && magic[1] == 0x8b;
}

InflatedDicomFiles::~InflatedDicomFiles() {
  std::error_code ec;
  if (!folder_.empty()) std::filesystem::remove_all(folder_, ec);
}

std::filesystem::path InflatedDicomFiles::add(const std::filesystem::path& gz) {
  const std::string what = gz.string();
  if (folder_.empty()) folder_ = make_inflate_folder(what);
  std::string stem = gz.filename().string();
  stem.resize(stem.size() - 3);  // without .gz
  const std::filesystem::path out = folder_ / fmt::format("{}_{}", names_.size(), stem);
  // A DICOM file is read into memory up to its pixels, and its pixels are charged whole: one
  // that inflates past the budget could never be read, and is not written out.
  const uint64_t budget = input_limits().max_memory;
  if (budget < kMaxInflatedDicomBytes)
    gunzip_file(gz, out, budget, what,
                fmt::format("more than the memory budget of {} (raise it with --max-memory)",
                            format_bytes(budget)));
  else
    gunzip_file(gz, out, kMaxInflatedDicomBytes, what, "not a DICOM file");
  names_.emplace_back(out.string(), what);
  return out;
}

std::string InflatedDicomFiles::original_names(std::string message) const {
  for (const auto& [temporary, original] : names_)
    for (size_t at = message.find(temporary); at != std::string::npos;
         at = message.find(temporary, at + original.size()))
      message.replace(at, temporary.size(), original);
  return message;
}

}  // namespace imx::detail
