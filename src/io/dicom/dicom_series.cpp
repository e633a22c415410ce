#include "io/dicom/dicom_series.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <map>
#include <system_error>

#include <fmt/format.h>
#include <gdcmReader.h>
#include <glm/geometric.hpp>

#include "intermix/error.hpp"
#include "io/dicom/dicom_structure.hpp"
#include "io/dicom/dicom_tags.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"

namespace imx::detail {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// A DICOMDIR by name or by its media storage class (Philips writes one called DIRFILE).
bool is_dicomdir(const std::filesystem::path& file) {
  if (lower(file.filename().string()) == "dicomdir") return true;
  if (!looks_like_dicom(file) || !file_meta_fault(file).empty() ||
      !check_dicom_structure(file).empty())
    return false;
  quiet_gdcm();
  InputFd fd;
  try {
    fd = open_input(file);
  } catch (const Error&) {
    return false;
  }
  gdcm::Reader reader;
  reader.SetFileName(path_of_open(fd, file).c_str());
  std::set<gdcm::Tag> skip;
  try {
    if (!reader.ReadUpToTag(gdcm::Tag(0x0004, 0x1220), skip)) return false;
  } catch (...) {
    return false;
  }
  return tag_text(reader.GetFile().GetHeader(), 0x0002, 0x0002).value_or("") ==
         "1.2.840.10008.1.3.10";
}

// A file or folder that could not be read: why, and the errno when it could not be opened.
struct BrokenFile {
  std::string message;
  int code = 0;
};

// Every regular file below `folder` (links to files followed, links to folders not: no loops),
// sorted. A folder below it that cannot be listed is added to `unlisted`, saying why: its files
// could be a series' slices. `folder` itself that cannot be listed is an imx::FileError.
std::vector<std::filesystem::path> files_under(const std::filesystem::path& folder,
                                               std::vector<BrokenFile>& unlisted) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  std::vector<std::pair<fs::path, int>> pending{{folder, 0}};  // a folder, its entries' depth
  while (!pending.empty()) {
    const auto [dir, depth] = pending.back();
    pending.pop_back();
    std::error_code ec;
    fs::directory_iterator it(dir, ec);
    for (; !ec && it != fs::directory_iterator(); it.increment(ec)) {
      std::error_code type_ec;
      if (it->is_directory(type_ec) && !it->is_symlink(type_ec)) {
        if (depth < kMaxDicomDepth) pending.emplace_back(it->path(), depth + 1);
        continue;
      }
      if (!it->is_regular_file(type_ec)) continue;  // FIFOs, devices, broken links, link loops
      if (files.size() >= static_cast<size_t>(kMaxDicomFiles))
        throw Error(fmt::format("{}: more than {} files below it; name the series' own folder",
                                folder.string(), kMaxDicomFiles));
      files.push_back(it->path());
    }
    if (!ec) continue;
    const std::string why =
        fmt::format("{}: cannot read the folder: {}", dir.string(), std::strerror(ec.value()));
    if (dir == folder) throw FileError(why, ec.value());
    unlisted.push_back({why, ec.value()});
  }
  std::sort(files.begin(), files.end());
  return files;
}

// A file that could not be opened or listed stays an imx::FileError (a PermissionError in
// Python); one whose content is at fault an imx::Error.
[[noreturn]] void throw_broken(const BrokenFile& b) {
  if (b.code != 0) throw FileError(b.message, b.code);
  throw Error(b.message);
}

bool same_direction(const std::optional<glm::dvec3>& a, const std::optional<glm::dvec3>& b) {
  if (a.has_value() != b.has_value()) return false;
  return !a || glm::dot(*a, *b) > 0.9999;  // within about 0.8 degrees
}

bool same_orientation(const DicomFrame& a, const DicomFrame& b) {
  return same_direction(a.row_direction, b.row_direction) &&
         same_direction(a.column_direction, b.column_direction);
}

}  // namespace

std::string original_names(const DicomSeriesGroup& group, std::string message) {
  return group.inflated ? group.inflated->original_names(std::move(message)) : message;
}

std::string describe_series(const DicomSeriesInfo& s) {
  return fmt::format("{} '{}' {} {}x{}, {} slice{}{}", s.id, s.description,
                     s.modality.empty() ? "?" : s.modality, s.columns, s.rows, s.slices,
                     s.slices == 1 ? "" : "s", s.localizer ? " (localizer)" : "");
}

std::vector<DicomSeriesGroup> scan_dicom_series(const std::filesystem::path& source,
                                                std::vector<std::string>* broken,
                                                std::vector<std::string>* not_images,
                                                int* first_broken_code) {
  namespace fs = std::filesystem;
  const std::string what = source.string();
  std::error_code ec;
  fs::file_status status = fs::status(source, ec);
  std::vector<DicomFileHeader> headers;
  auto inflated = std::make_shared<InflatedDicomFiles>();  // .dcm.gz files, inflated
  bool folder = !ec && fs::is_directory(status);
  if (!folder) {
    // A file, then: the guarded open says what else it is (a FIFO, a device, a link loop).
    try {
      require_regular_file(source);
    } catch (const FileError& e) {
      if (e.code() == ENOENT && !fs::is_symlink(fs::symlink_status(source, ec)))
        throw FileError(fmt::format("{}: no such file or folder", what), ENOENT);
      throw;
    }
    if (is_dicomdir(source)) {
      folder = true;  // its records often name paths that moved: the folder is the truth
    } else {
      fs::path readable = source;
      if (is_gzip_file(source)) readable = inflated->add(source);
      std::optional<DicomFileHeader> h;
      std::string not_image;
      try {
        h = read_dicom_header(readable, &not_image);
      } catch (const FileError& e) {
        throw FileError(inflated->original_names(e.what()), e.code());
      } catch (const Error& e) {
        throw Error(inflated->original_names(e.what()));
      }
      if (!h) throw Error(fmt::format("{}: {}", what, not_image));
      headers.push_back(std::move(*h));
    }
  }
  if (folder) {
    const fs::path dir = fs::is_directory(status) ? source : source.parent_path();
    std::vector<BrokenFile> unreadable;
    for (const fs::path& f : files_under(dir.empty() ? fs::path(".") : dir, unreadable)) {
      try {
        const fs::path readable = is_gzip_file(f) ? inflated->add(f) : f;
        if (std::optional<DicomFileHeader> h = read_dicom_header(readable))
          headers.push_back(std::move(*h));
        else if (not_images != nullptr)
          not_images->push_back(f.string());
      } catch (const FileError& e) {
        unreadable.push_back({inflated->original_names(e.what()), e.code()});
      } catch (const Error& e) {
        unreadable.push_back({inflated->original_names(e.what()), 0});
      }
    }
    if (broken != nullptr)
      for (const BrokenFile& b : unreadable) broken->push_back(b.message);
    if (first_broken_code != nullptr && !unreadable.empty())
      *first_broken_code = unreadable.front().code;
    if (headers.empty() && !unreadable.empty()) throw_broken(unreadable.front());
    if (headers.empty()) {
      // A folder named like a file ("x.nrrd/") was most likely meant as that file.
      const std::string ext = fs::path(what).extension().string();
      if (fs::is_directory(status) && !ext.empty())
        throw Error(fmt::format("{}: a folder, not a '{}' file, and it holds no DICOM image files",
                                what, ext));
      throw Error(fmt::format("{}: no DICOM image files in {}", what,
                              fs::is_directory(status) ? "this folder" : "its folder"));
    }
  }

  // Group by series UID and number (one UID may carry several numbers: dcm2niix makes a volume
  // of each), size, localizer-ness, then by orientation within those.
  // Derived diffusion images (ADC, trace), colour images and the two polarities of GE's
  // alternating epi_pepolar sharing one UID are series of their own too, as dcm2niix converts
  // them apart.
  std::map<std::tuple<std::string, int, int, int, bool, bool, int, int>,
           std::vector<std::vector<DicomFileHeader>>>
      keyed;
  for (DicomFileHeader& h : headers) {
    const bool derived = std::all_of(h.frames.begin(), h.frames.end(),
                                     [](const DicomFrame& f) { return f.derived_diffusion; });
    auto& clusters = keyed[{h.series_uid, h.series_number, h.rows, h.columns, h.localizer,
                            derived && !h.frames.empty(), h.samples_per_pixel, h.polarity_part}];
    auto it = std::find_if(clusters.begin(), clusters.end(), [&](const auto& c) {
      return same_orientation(c.front().frames.front(), h.frames.front());
    });
    if (it == clusters.end()) {
      clusters.emplace_back();
      it = clusters.end() - 1;
    }
    it->push_back(std::move(h));
  }
  std::map<std::pair<std::string, int>, std::vector<DicomSeriesGroup>> by_uid;
  for (auto& [key, clusters] : keyed)
    for (auto& files : clusters) {
      DicomSeriesGroup g;
      const DicomFileHeader& first = files.front();
      g.info.uid = first.series_uid;
      g.info.number = first.series_number;
      g.info.description = first.description;
      g.info.modality = first.modality;
      g.info.rows = first.rows;
      g.info.columns = first.columns;
      g.info.localizer = first.localizer;
      g.info.row_direction = first.frames.front().row_direction.value_or(glm::dvec3(0.0));
      g.info.column_direction = first.frames.front().column_direction.value_or(glm::dvec3(0.0));
      for (const DicomFileHeader& h : files) {
        g.info.slices += h.frame_count;
        g.info.files.push_back(inflated->original_names(h.file.string()));
      }
      g.headers = std::move(files);
      g.inflated = inflated;
      by_uid[{g.info.uid, g.info.number}].push_back(std::move(g));
    }
  std::vector<DicomSeriesGroup> out;
  for (auto& [uid, parts] : by_uid) {
    std::stable_sort(parts.begin(), parts.end(), [](const auto& a, const auto& b) {
      if (a.info.localizer != b.info.localizer) return !a.info.localizer;
      return a.info.slices > b.info.slices;
    });
    for (size_t p = 0; p < parts.size(); ++p) {
      parts[p].info.part = parts.size() > 1 ? static_cast<int>(p) + 1 : 0;
      parts[p].info.id = parts.size() > 1 ? fmt::format("{}.{}", parts[p].info.number, p + 1)
                                          : fmt::format("{}", parts[p].info.number);
      out.push_back(std::move(parts[p]));
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return std::tie(a.info.number, a.info.part, a.info.uid) <
           std::tie(b.info.number, b.info.part, b.info.uid);
  });
  return out;
}

const DicomSeriesGroup& choose_series(const std::vector<DicomSeriesGroup>& groups,
                                      const std::string& choice,
                                      const std::filesystem::path& source, std::string& note) {
  auto listing = [&] {
    std::string s;
    // One line, as every error is: the series separated by semicolons.
    for (const DicomSeriesGroup& g : groups)
      s += (s.empty() ? " " : "; ") + describe_series(g.info);
    return s;
  };
  const DicomSeriesGroup* chosen = nullptr;
  if (choice.empty()) {
    auto voxels = [](const DicomSeriesGroup& g) {
      return static_cast<double>(g.info.rows) * g.info.columns * g.info.slices;
    };
    for (const DicomSeriesGroup& g : groups)  // largest non-localizer, else largest
      if (chosen == nullptr || (chosen->info.localizer && !g.info.localizer) ||
          (chosen->info.localizer == g.info.localizer && voxels(g) > voxels(*chosen)))
        chosen = &g;
  } else {
    std::vector<const DicomSeriesGroup*> matches;
    for (const DicomSeriesGroup& g : groups)
      if (g.info.id == choice || g.info.uid == choice || std::to_string(g.info.number) == choice)
        matches.push_back(&g);
    if (matches.empty())
      throw Error(
          fmt::format("{}: no series '{}'; the series are (id 'description' modality "
                      "size):{}",
                      source.string(), choice, listing()));
    if (matches.size() > 1) {
      std::string which;
      for (const DicomSeriesGroup* g : matches)
        which += fmt::format("{}{} (UID {})", which.empty() ? " " : "; ", describe_series(g->info),
                             g->info.uid);
      const bool same_ids = std::all_of(matches.begin(), matches.end(),
                                        [&](const auto* g) { return g->info.id == choice; });
      throw Error(fmt::format("{}: series '{}' is ambiguous: it matches {} series:{}; give {}",
                              source.string(), choice, matches.size(), which,
                              same_ids ? "a SeriesInstanceUID"
                                       : fmt::format("an id such as '{}', or a SeriesInstanceUID",
                                                     matches.front()->info.id)));
    }
    chosen = matches.front();
  }
  if (groups.size() > 1)
    note = fmt::format("loaded series {} '{}' of {} series", chosen->info.id,
                       chosen->info.description, groups.size());
  return *chosen;
}

}  // namespace imx::detail
