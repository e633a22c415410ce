// read_volume(folder) without recursive=True: the folder's own DICOM files only.
#include "dicom_folder.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <string>
#include <system_error>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "intermix/error.hpp"

namespace imx::python {
namespace {

namespace fs = std::filesystem;

constexpr size_t kNamedSubfolders = 3;  // an error names this many subfolders, then a count

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

// A temporary folder, removed with what it holds.
struct TemporaryFolder {
  fs::path path;
  TemporaryFolder() {
    std::string pattern = (fs::temp_directory_path() / "intermix-dicom-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr)
      throw FileError(
          fmt::format("cannot create a temporary folder in {}", fs::temp_directory_path().string()),
          errno);
    path = pattern;
  }
  ~TemporaryFolder() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

}  // namespace

void read_dicom_source(const fs::path& source, bool recursive, const char* function,
                       const std::function<void(const fs::path&)>& read) {
  std::error_code ec;
  if (recursive || !fs::is_directory(source, ec)) return read(source);
  std::vector<fs::path> files;
  std::vector<std::string> subfolders;
  for (fs::directory_iterator it(source, fs::directory_options::skip_permission_denied, ec), end;
       !ec && it != end; it.increment(ec)) {
    std::error_code type_ec;
    if (it->is_directory(type_ec))
      subfolders.push_back(it->path().filename().string());
    else if (it->is_regular_file(type_ec))
      files.push_back(it->path());
  }
  if (ec)
    throw FileError(fmt::format("{}: cannot read the folder: {}", source.string(), ec.message()),
                    ec.value());
  if (subfolders.empty()) return read(source);
  std::sort(subfolders.begin(), subfolders.end());
  const size_t named = std::min(subfolders.size(), kNamedSubfolders);
  const std::string listed =
      fmt::format("{}{}", fmt::join(subfolders.begin(), subfolders.begin() + named, ", "),
                  subfolders.size() > named ? fmt::format(" and {} more", subfolders.size() - named)
                                            : std::string());
  if (files.empty())
    throw Error(fmt::format(
        "{}: no file in this folder itself, only subfolders ({}); name the series' folder, or "
        "pass recursive=True to {} to search below it",
        source.string(), listed, function));
  // The engine's reader scans a folder whole: it reads a folder of links to these files alone.
  TemporaryFolder links;
  for (const fs::path& file : files) {
    fs::create_symlink(fs::absolute(file), links.path / file.filename(), ec);
    if (ec)
      throw FileError(fmt::format("{}: cannot link {} into {}: {}", source.string(), file.string(),
                                  links.path.string(), ec.message()),
                      ec.value());
  }
  const std::string from = links.path.string(), to = source.string();
  try {
    read(links.path);
  } catch (const FileError& e) {
    throw FileError(replaced(e.what(), from, to), e.code());
  } catch (const OutOfMemory& e) {
    throw OutOfMemory(replaced(e.what(), from, to));
  } catch (const Cancelled&) {
    throw;
  } catch (const Error& e) {
    throw Error(replaced(e.what(), from, to));
  }
}

}  // namespace imx::python
