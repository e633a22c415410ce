#include "io/dicom/dicom_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/dicom/dicom_pixels.hpp"
#include "io/dicom/dicom_series.hpp"
#include "io/dicom/dicom_suv.hpp"

namespace imx {

namespace detail {

AcquiredSeries read_acquired_series(const std::filesystem::path& source,
                                    const std::string& series) {
  const std::string what = source.string();
  std::vector<std::string> broken;
  std::vector<DicomSeriesGroup> groups = scan_dicom_series(source, &broken);
  // A slice that cannot be read would leave a hole in whichever series it belongs to.
  if (!broken.empty())
    throw Error(broken.size() == 1 ? broken.front()
                                   : fmt::format("{} (and {} more such files)", broken.front(),
                                                 broken.size() - 1));
  std::string note;
  const DicomSeriesGroup& group = choose_series(groups, series, source, note);
  AcquiredSeries out;
  out.info = group.info;
  if (!note.empty()) out.notes.push_back(note);
  const DicomFileHeader& first = group.headers.front();
  out.modality = first.modality;
  out.photometric = first.photometric;
  out.rescale_type = first.rescale_type;
  out.suv = first.suv;

  std::vector<DicomFrame> frames;
  for (const DicomFileHeader& h : group.headers)
    frames.insert(frames.end(), h.frames.begin(), h.frames.end());
  const std::string series_what = fmt::format("{} (series {})", what, group.info.id);
  out.stack =
      order_slices(std::move(frames), first.rows, first.columns, first.slice_spacing, series_what);
  const size_t plane = static_cast<size_t>(first.rows) * first.columns;
  check_memory(plane * out.stack.frames.size() * sizeof(float),
               fmt::format("{} ({}x{}x{} voxels)", series_what, first.columns, first.rows,
                           out.stack.frames.size()));

  // Decode each file once; a multi-frame file fills several slices.
  std::map<std::filesystem::path, std::vector<size_t>> slots;  // file -> sorted slice indices
  for (size_t s = 0; s < out.stack.frames.size(); ++s) slots[out.stack.frames[s].file].push_back(s);
  out.values.resize(out.stack.frames.size());
  const double slope = out.stack.frames.front().slope;
  // Files decode independently (one GDCM reader each), into distinct slices.
  std::vector<char> integer_pixels(group.headers.size(), 1);
  tbb::parallel_for(size_t{0}, group.headers.size(), [&](size_t i) {
    const DicomFileHeader& h = group.headers[i];
    DecodedFrames decoded = decode_dicom_frames(h);
    integer_pixels[i] = decoded.integer_pixels;
    for (size_t s : slots.at(h.file))
      out.values[s] = std::move(decoded.frames[static_cast<size_t>(out.stack.frames[s].frame)]);
  });
  for (size_t i = 0; i < group.headers.size(); ++i)
    out.integer_valued = out.integer_valued && integer_pixels[i];
  for (const DicomFrame& f : out.stack.frames)
    if (f.slope != slope || f.slope != std::round(f.slope) ||
        f.intercept != std::round(f.intercept))
      out.integer_valued = false;
  if (out.photometric == "MONOCHROME1")
    out.notes.push_back("MONOCHROME1: low values display bright; the values are kept as stored");
  return out;
}

}  // namespace detail

namespace {

template <class T>
VoxelStorage fill(const detail::AcquiredSeries& a, const detail::SliceGrid& grid, double scale) {
  const size_t plane = a.values.front().size();
  std::vector<T> out(plane * grid.blends.size());
  tbb::parallel_for(size_t{0}, grid.blends.size(), [&](size_t k) {
    const detail::SliceBlend b = grid.blends[k];
    const detail::FloatPlane& lo = a.values[static_cast<size_t>(b.lower)];
    T* dst = out.data() + k * plane;
    if (b.weight == 0.0 && scale == 1.0) {
      for (size_t i = 0; i < plane; ++i) dst[i] = static_cast<T>(lo[i]);
    } else {
      const detail::FloatPlane& hi = a.values[static_cast<size_t>(b.lower) + 1 < a.values.size()
                                                  ? static_cast<size_t>(b.lower) + 1
                                                  : static_cast<size_t>(b.lower)];
      const double w = b.weight;
      for (size_t i = 0; i < plane; ++i)
        dst[i] = static_cast<T>(((1.0 - w) * lo[i] + w * hi[i]) * scale);
    }
  });
  return out;
}

// Smallest and largest value of a plane (finite: the decoder checked), in eight independent
// lanes so that the compiler vectorizes it; one running pair was a sixth of read_dicom.
std::pair<float, float> plane_range(const detail::FloatPlane& p) {
  constexpr int kLanes = 8;
  float lo[kLanes], hi[kLanes];
  std::fill(lo, lo + kLanes, std::numeric_limits<float>::infinity());
  std::fill(hi, hi + kLanes, -std::numeric_limits<float>::infinity());
  size_t i = 0;
  for (; i + kLanes <= p.size(); i += kLanes)
    for (int j = 0; j < kLanes; ++j) {
      lo[j] = std::min(lo[j], p[i + j]);
      hi[j] = std::max(hi[j], p[i + j]);
    }
  for (; i < p.size(); ++i) {
    lo[0] = std::min(lo[0], p[i]);
    hi[0] = std::max(hi[0], p[i]);
  }
  return {*std::min_element(lo, lo + kLanes), *std::max_element(hi, hi + kLanes)};
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace

std::vector<DicomSeriesInfo> list_dicom_series(const std::filesystem::path& source) {
  std::vector<DicomSeriesInfo> out;
  for (detail::DicomSeriesGroup& g : detail::scan_dicom_series(source))
    out.push_back(std::move(g.info));
  return out;
}

DicomVolume read_dicom(const std::filesystem::path& source, const DicomReadOptions& options) {
  const std::string what = source.string();
  if (!options.units.empty() && options.units != "suv")
    throw Error(
        fmt::format("{}: units '{}' is not known (give \"suv\" or nothing)", what, options.units));
  detail::AcquiredSeries a = detail::read_acquired_series(source, options.series);
  const std::string series_what = fmt::format("{} (series {})", what, a.info.id);
  detail::SliceGrid grid = detail::plan_slice_grid(a.stack, options.slice_spacing_mm, series_what);

  DicomVolume out;
  out.series = a.info;
  out.notes = a.notes;
  out.notes.insert(out.notes.end(), a.stack.notes.begin(), a.stack.notes.end());
  if (a.modality == "CT")
    out.units = a.rescale_type.empty() ? "HU" : a.rescale_type;
  else if (a.modality == "PT")
    out.units = a.suv.units.value_or(a.rescale_type);
  else
    out.units = a.rescale_type;
  double scale = 1.0;
  if (options.units == "suv") {
    scale = detail::suv_body_weight_factor(a.suv, series_what);
    out.units = "g/ml";
    out.notes.push_back(
        fmt::format("SUV by body weight: activity concentration times {:.6g}", scale));
  }
  if (const auto& w = a.stack.frames.front().window) out.window = *w * scale;

  const size_t plane = static_cast<size_t>(a.stack.rows) * a.stack.columns;
  std::vector<std::pair<float, float>> ranges(a.values.size());
  tbb::parallel_for(size_t{0}, a.values.size(),
                    [&](size_t s) { ranges[s] = plane_range(a.values[s]); });
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (auto [l, h] : ranges) {
    lo = std::min(lo, l);
    hi = std::max(hi, h);
  }
  VoxelType type = VoxelType::f32;
  if (a.integer_valued && !grid.resampled && scale == 1.0) {
    if (lo >= 0 && hi <= 255)
      type = VoxelType::u8;
    else if (lo >= -32768 && hi <= 32767)
      type = VoxelType::i16;
    else if (lo >= 0 && hi <= 65535)
      type = VoxelType::u16;
  }
  const size_t sizes[] = {1, 2, 2, 4};
  check_memory(plane * grid.blends.size() * sizes[static_cast<int>(type)],
               fmt::format("{} ({}x{}x{} voxels)", series_what, a.stack.columns, a.stack.rows,
                           grid.blends.size()));
  VolumeData& v = out.volume;
  v.dims = {a.stack.columns, a.stack.rows, static_cast<int>(grid.blends.size())};
  v.index_to_world = grid.index_to_world;
  switch (type) {
    case VoxelType::u8:
      v.voxels = fill<uint8_t>(a, grid, scale);
      break;
    case VoxelType::i16:
      v.voxels = fill<int16_t>(a, grid, scale);
      break;
    case VoxelType::u16:
      v.voxels = fill<uint16_t>(a, grid, scale);
      break;
    case VoxelType::f32:
      v.voxels = fill<float>(a, grid, scale);
      break;
  }
  out.series.slices = static_cast<int>(a.stack.frames.size());
  v.validate(series_what);
  return out;
}

bool is_dicom_source(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return true;
  const std::string name = lower(path.filename().string());
  if (name == "dicomdir") return true;
  const std::string ext = lower(path.extension().string());
  if (ext == ".dcm" || ext == ".dicom") return true;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  char head[132] = {};
  in.read(head, sizeof head);
  return in.gcount() == 132 && std::memcmp(head + 128, "DICM", 4) == 0;
}

VolumeHeader read_dicom_header(const std::filesystem::path& source,
                               const DicomReadOptions& options) {
  DicomVolume d = read_dicom(source, options);
  return {d.volume.dims, d.volume.type(), d.volume.index_to_world, d.frames, d.frame_labels};
}

}  // namespace imx
