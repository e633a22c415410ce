#include "io/tiff/tiff_layout.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/tiff/imagej_description.hpp"
#include "io/tiff/ome_xml.hpp"
#include "io/voxels/frame_voxels.hpp"
#include "io/voxels/length_units.hpp"

namespace imx::detail {

namespace {

// More planes than this (z times channels times time points) is corrupt metadata.
constexpr int64_t kMaxPlanes = int64_t{1} << 24;

double mm_per(const std::string& unit, const std::string& field, const std::string& what) {
  if (const std::optional<double> mm = millimetres_per_unit(unit)) return *mm;
  throw Error(
      fmt::format("{}: {} has unit '{}': read are {}", what, field, unit, length_units_read()));
}

// Pixel size from the resolution tags (pixels per inch or centimetre); 1 mm without a unit.
glm::dvec2 resolution_spacing(const TiffPage& page) {
  const double per_unit = page.resolution_unit == 2 ? 25.4 : page.resolution_unit == 3 ? 10 : 0;
  glm::dvec2 s(1.0);
  if (per_unit > 0 && page.x_resolution > 0 && std::isfinite(page.x_resolution))
    s.x = per_unit / page.x_resolution;
  if (per_unit > 0 && page.y_resolution > 0 && std::isfinite(page.y_resolution))
    s.y = per_unit / page.y_resolution;
  return s;
}

void check_grid(TiffLayout& l, int64_t x, int64_t y, int64_t z, const std::string& field) {
  // Past kMaxVoxels a grid is read by region (a render in bricks); in double: no overflow.
  if (x < 1 || y < 1 || z < 1 || x > INT32_MAX || y > INT32_MAX || z > INT32_MAX ||
      static_cast<double>(x) * static_cast<double>(y) * static_cast<double>(z) >
          static_cast<double>(kMaxGridVoxels))
    throw Error(fmt::format("{}: {}: a grid of {} x {} x {} voxels (at most {} are read)", l.what,
                            field, x, y, z, kMaxGridVoxels));
  l.dims = glm::ivec3(static_cast<int>(x), static_cast<int>(y), static_cast<int>(z));
}

void check_frames(const TiffLayout& l, int64_t channels, int64_t frames, const std::string& field) {
  if (channels > kMaxFrames || frames > kMaxFrames || channels * frames * l.dims.z > kMaxPlanes)
    throw Error(
        fmt::format("{}: {}: {} channels and {} time points of {} slices, more planes "
                    "than the {} read",
                    l.what, field, channels, frames, l.dims.z, kMaxPlanes));
}

// A page a plane names: within the file, and a slice page like the first.
void check_planes(TiffLayout& l) {
  const std::vector<TiffPage>& pages = l.opened->pages();
  for (size_t n = 0; n < l.planes.size(); ++n) {
    const int directory = l.planes[n].directory;
    const int z = static_cast<int>(n % l.dims.z), rest = static_cast<int>(n / l.dims.z);
    if (directory < 0 || static_cast<size_t>(directory) >= pages.size())
      throw Error(
          fmt::format("{}: slice {} of channel {}, time point {} is in page {}, but the "
                      "file has {} pages",
                      l.what, z, rest % l.channels, rest / l.channels, directory, pages.size()));
    check_slice_page(l, pages[directory], l.what);
  }
}

// The pages of a file that are slices (not reduced-resolution copies), as directory numbers.
std::vector<int> full_pages(const TiffFile& f) {
  std::vector<int> out;
  for (const TiffPage& p : f.pages())
    if (!p.reduced) out.push_back(p.directory);
  return out;
}

RawType ome_type(const std::string& type, const std::string& what) {
  static const std::pair<const char*, RawType> kTypes[] = {
      {"int8", RawType::i8},    {"uint8", RawType::u8},  {"int16", RawType::i16},
      {"uint16", RawType::u16}, {"int32", RawType::i32}, {"uint32", RawType::u32},
      {"float", RawType::f32},  {"double", RawType::f64}};
  for (const auto& [name, t] : kTypes)
    if (type == name) return t;
  throw Error(
      fmt::format("{}: OME-XML Pixels Type '{}' is not read (read are int8, uint8, int16, "
                  "uint16, int32, uint32, float and double)",
                  what, type));
}

void ome_layout(TiffLayout& l, const std::filesystem::path& file) {
  const OmePixels px = parse_ome_xml(l.opened->description(), l.what);
  if (px.samples_per_pixel > 1)
    throw Error(
        fmt::format("{}: OME-XML Channel SamplesPerPixel {}: interleaved colour channels "
                    "are not read",
                    l.what, px.samples_per_pixel));
  check_grid(l, px.size_x, px.size_y, px.size_z, "OME-XML SizeX, SizeY, SizeZ");
  check_frames(l, px.size_c, px.size_t_, "OME-XML SizeC, SizeT");
  l.channels = static_cast<int>(px.size_c);
  l.frames = static_cast<int>(px.size_t_);
  l.type = ome_type(px.type, l.what);
  const int64_t total = px.size_z * px.size_c * px.size_t_;
  std::vector<int64_t> ifd(total, -1);
  if (px.tiff_data.empty())
    for (int64_t p = 0; p < total; ++p) ifd[p] = p;
  for (const OmeTiffData& td : px.tiff_data) {
    if (!td.file_name.empty() && td.file_name != file.filename().string())
      throw Error(
          fmt::format("{}: OME-XML TiffData names file '{}': only single-file OME-TIFF "
                      "is read",
                      l.what, td.file_name));
    if (td.first_z >= px.size_z || td.first_c >= px.size_c || td.first_t >= px.size_t_)
      throw Error(fmt::format("{}: OME-XML TiffData FirstZ/C/T {}/{}/{} outside the image", l.what,
                              td.first_z, td.first_c, td.first_t));
    const int64_t start = px.plane_index(td.first_z, td.first_c, td.first_t);
    // OME: PlaneCount defaults to 1 when IFD is given, else to every plane from there.
    const int64_t count = td.plane_count.value_or(td.ifd ? 1 : total - start);
    for (int64_t i = 0; i < count && start + i < total; ++i)
      ifd[start + i] = td.ifd.value_or(0) + i;
  }
  l.planes.resize(total);
  for (int64_t t = 0; t < px.size_t_; ++t)
    for (int64_t c = 0; c < px.size_c; ++c)
      for (int64_t z = 0; z < px.size_z; ++z) {
        const int64_t d = ifd[px.plane_index(z, c, t)];
        if (d < 0)
          throw Error(fmt::format("{}: OME-XML TiffData gives no page for z={}, c={}, t={}", l.what,
                                  z, c, t));
        l.planes[z + px.size_z * (c + px.size_c * t)] = {
            0, static_cast<int>(std::min<int64_t>(d, int64_t{1} << 30))};
      }
  const char* axes[] = {"PhysicalSizeX", "PhysicalSizeY", "PhysicalSizeZ"};
  for (int a = 0; a < 3; ++a)
    if (px.physical_size[a])
      l.spacing[a] = *px.physical_size[a] *
                     mm_per(px.physical_unit[a], fmt::format("OME-XML {}", axes[a]), l.what);
}

// ImageJ's calibration: XResolution counts pixels per `unit` (whatever ResolutionUnit says) and
// `spacing` is the z step in it; without a unit, the resolution tags' and spacing in mm.
glm::dvec3 imagej_spacing(const TiffPage& first, const ImageJDescription& ij,
                          const std::string& what) {
  if (ij.unit.empty() || ij.unit == "pixel")
    return glm::dvec3(resolution_spacing(first), ij.spacing.value_or(1.0));
  const double mm = mm_per(ij.unit, "ImageJ description 'unit'", what);
  glm::dvec3 s(mm);
  if (first.x_resolution > 0 && std::isfinite(first.x_resolution)) s.x /= first.x_resolution;
  if (first.y_resolution > 0 && std::isfinite(first.y_resolution)) s.y /= first.y_resolution;
  if (ij.spacing) s.z = *ij.spacing * mm;
  return s;
}

void imagej_layout(TiffLayout& l, const std::vector<int>& pages) {
  const ImageJDescription ij = parse_imagej_description(l.opened->description(), l.what);
  int64_t slices = ij.slices;
  if (slices == 0) slices = std::max<int64_t>(1, ij.images / (ij.channels * ij.frames));
  const int64_t images = ij.images ? ij.images : slices * ij.channels * ij.frames;
  if (slices * ij.channels * ij.frames != images)
    throw Error(
        fmt::format("{}: ImageJ description: images={} is not channels={} x slices={} x "
                    "frames={}",
                    l.what, images, ij.channels, slices, ij.frames));
  if (static_cast<size_t>(images) > pages.size())
    throw Error(
        fmt::format("{}: ImageJ description: images={}, but the file has {} pages "
                    "(ImageJ's single-page layout of files over 4 GB is not read)",
                    l.what, images, pages.size()));
  const TiffPage& first = l.opened->pages()[pages[0]];
  check_grid(l, first.width, first.height, slices, "ImageJ slices");
  check_frames(l, ij.channels, ij.frames, "ImageJ channels, frames");
  l.channels = static_cast<int>(ij.channels);
  l.frames = static_cast<int>(ij.frames);
  // ImageJ's order: channel fastest, then slice, then frame.
  l.planes.resize(images);
  for (int64_t t = 0; t < ij.frames; ++t)
    for (int64_t c = 0; c < ij.channels; ++c)
      for (int64_t z = 0; z < slices; ++z)
        l.planes[z + slices * (c + ij.channels * t)] = {0,
                                                        pages[(t * slices + z) * ij.channels + c]};
  l.spacing = imagej_spacing(first, ij, l.what);
}

TiffLayout file_layout(const std::filesystem::path& file) {
  TiffLayout l;
  l.what = file.string();
  l.files = {file};
  l.opened = std::make_shared<TiffFile>(file);
  const std::vector<int> pages = full_pages(*l.opened);
  if (pages.empty())
    throw Error(fmt::format("{}: every page is a reduced-resolution copy", l.what));
  const TiffPage& first = l.opened->pages()[pages[0]];
  const std::string& description = l.opened->description();
  if (is_ome_xml(description)) {
    ome_layout(l, file);
  } else if (is_imagej_description(description)) {
    imagej_layout(l, pages);
  } else {
    check_grid(l, first.width, first.height, static_cast<int64_t>(pages.size()), "page count");
    for (int d : pages) l.planes.push_back({0, d});
    l.spacing = glm::dvec3(resolution_spacing(first), 1.0);
  }
  const TiffPage& base = l.opened->pages()[l.planes.empty() ? pages[0] : l.planes[0].directory];
  if (!is_ome_xml(description)) l.type = base.type;
  l.first_directory = static_cast<uint32_t>(base.directory);
  check_planes(l);
  return l;
}

TiffLayout folder_layout(const std::filesystem::path& dir) {
  TiffLayout l;
  l.what = dir.string();
  l.folder = true;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (!name.empty() && name[0] != '.' && entry.is_regular_file(ec))
      l.files.push_back(entry.path());
  }
  if (ec) throw Error(fmt::format("{}: cannot list the folder: {}", l.what, ec.message()));
  if (l.files.empty()) throw Error(fmt::format("{}: no TIFF files in the folder", l.what));
  std::sort(l.files.begin(), l.files.end(), [](const auto& a, const auto& b) {
    return natural_less(a.filename().string(), b.filename().string());
  });
  l.opened = std::make_shared<TiffFile>(l.files[0]);
  const std::vector<int> pages = full_pages(*l.opened);
  if (pages.size() != 1)
    throw Error(fmt::format("{}: {} pages: a folder stack takes one page per file",
                            l.files[0].string(), pages.size()));
  const TiffPage& first = l.opened->pages()[pages[0]];
  l.type = first.type;
  l.first_directory = static_cast<uint32_t>(first.directory);
  check_grid(l, first.width, first.height, static_cast<int64_t>(l.files.size()), "file count");
  check_slice_page(l, first, l.files[0].string());
  l.spacing = glm::dvec3(resolution_spacing(first), 1.0);
  const std::string& description = l.opened->description();
  if (is_imagej_description(description)) {
    const std::string what = l.files[0].string();
    l.spacing = imagej_spacing(first, parse_imagej_description(description, what), what);
  }
  return l;
}

}  // namespace

TiffPlane TiffLayout::plane(int z, int channel, int frame) const {
  if (folder) return {z, -1};  // the file's one full page
  return planes[z +
                static_cast<size_t>(dims.z) * (channel + static_cast<size_t>(channels) * frame)];
}

glm::dmat4 TiffLayout::index_to_world() const {
  glm::dmat4 m(1.0);
  for (int a = 0; a < 3; ++a) m[a][a] = spacing[a];
  return m;
}

void check_slice_page(const TiffLayout& l, const TiffPage& page, const std::string& what) {
  if (!page.problem.empty())
    throw Error(fmt::format("{}: page {}: {}", what, page.directory, page.problem));
  if (page.reduced)
    throw Error(fmt::format("{}: page {} is a reduced-resolution copy (NewSubfileType 1)", what,
                            page.directory));
  if (page.width != static_cast<uint32_t>(l.dims.x) ||
      page.height != static_cast<uint32_t>(l.dims.y))
    throw Error(
        fmt::format("{}: page {}: ImageWidth x ImageLength {} x {}, but the volume's "
                    "slices are {} x {}",
                    what, page.directory, page.width, page.height, l.dims.x, l.dims.y));
  if (page.type != l.type)
    throw Error(
        fmt::format("{}: page {}: BitsPerSample and SampleFormat give {}, but the "
                    "volume's slices are {}",
                    what, page.directory, raw_type_name(page.type), raw_type_name(l.type)));
}

bool natural_less(const std::string& a, const std::string& b) {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) &&
        std::isdigit(static_cast<unsigned char>(b[j]))) {
      size_t ie = i, je = j;
      while (ie < a.size() && std::isdigit(static_cast<unsigned char>(a[ie]))) ++ie;
      while (je < b.size() && std::isdigit(static_cast<unsigned char>(b[je]))) ++je;
      // Leading zeros aside, a longer run is a larger number.
      size_t is = i, js = j;
      while (is + 1 < ie && a[is] == '0') ++is;
      while (js + 1 < je && b[js] == '0') ++js;
      if (ie - is != je - js) return ie - is < je - js;
      if (const int c = a.compare(is, ie - is, b, js, je - js); c != 0) return c < 0;
      i = ie, j = je;
    } else {
      if (a[i] != b[j]) return static_cast<unsigned char>(a[i]) < static_cast<unsigned char>(b[j]);
      ++i, ++j;
    }
  }
  if (a.size() - i != b.size() - j) return a.size() - i < b.size() - j;
  return a < b;
}

TiffLayout tiff_layout(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return folder_layout(path);
  return file_layout(path);
}

}  // namespace imx::detail
