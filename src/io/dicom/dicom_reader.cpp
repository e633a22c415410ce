#include "io/dicom/dicom_reader.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <tuple>

#include <sys/mman.h>

#include <cstdlib>
#include <new>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/dicom/dicom_pixels.hpp"
#include "io/dicom/dicom_series.hpp"
#include "io/dicom/dicom_suv.hpp"
#include "io/dicom/dicom_volumes.hpp"
#include "io/registry/tiff_sniff.hpp"
#include "io/streams/input_file.hpp"
#include "io/voxels/frames.hpp"

namespace imx {

namespace detail {

namespace {

// The series chosen, split into volumes: what every read starts from.
struct SeriesLayout {
  DicomSeriesGroup group;
  DicomVolumes volumes;
  std::string note, what;
  std::vector<std::string> notes;       // the files' and the volumes' notes, each once
  std::vector<std::string> not_images;  // files beside the series that are not DICOM images
};

// A series none of whose images has an ImagePositionPatient (some UIH DTI series): stacked as
// dcm2niix stacks them, in acquisition order along the patient axes (ImageOrientationPatient
// ignored, as it ignores it), PixelSpacing and SpacingBetweenSlices (else SliceThickness, else
// 1 mm) apart, centred on the origin. Returns the note that says so.
std::string place_without_positions(std::vector<DicomFrame>& images, const DicomFileHeader& h) {
  std::stable_sort(images.begin(), images.end(), [](const DicomFrame& a, const DicomFrame& b) {
    return std::tie(a.instance_number, a.file, a.frame) <
           std::tie(b.instance_number, b.file, b.frame);
  });
  const glm::dvec2 pixel = images.front().pixel_spacing.value_or(glm::dvec2(1.0));
  const double step = h.slice_spacing.value_or(1.0);
  const glm::dvec3 first(-(h.columns - 1) * pixel.y / 2.0, -(h.rows - 1) * pixel.x / 2.0,
                         -static_cast<double>(images.size() - 1) * step / 2.0);
  for (size_t k = 0; k < images.size(); ++k) {
    images[k].row_direction = glm::dvec3(1.0, 0.0, 0.0);
    images[k].column_direction = glm::dvec3(0.0, 1.0, 0.0);
    images[k].position = first + glm::dvec3(0.0, 0.0, step * static_cast<double>(k));
  }
  return fmt::format(
      "no ImagePositionPatient (0020,0032): the {} images are stacked in acquisition order "
      "{:g} mm apart along the patient axes, centred on the origin, as dcm2niix places them "
      "(the real placement is unknown)",
      images.size(), step);
}

SeriesLayout layout_of(const std::filesystem::path& source, const std::string& series) {
  std::vector<std::string> broken, not_images;
  int broken_code = 0;
  std::vector<DicomSeriesGroup> groups =
      scan_dicom_series(source, &broken, &not_images, &broken_code);
  // A slice that cannot be read would leave a hole in whichever series it belongs to.
  if (!broken.empty()) {
    const std::string message = broken.size() == 1 ? broken.front()
                                                   : fmt::format("{} (and {} more such files)",
                                                                 broken.front(), broken.size() - 1);
    if (broken_code != 0) throw FileError(message, broken_code);  // a PermissionError in Python
    throw Error(message);
  }
  SeriesLayout l;
  l.not_images = std::move(not_images);
  l.group = choose_series(groups, series, source, l.note);
  l.what = fmt::format("{} (series {})", source.string(), l.group.info.id);
  for (const DicomFileHeader& h : l.group.headers)
    for (const std::string& n : h.notes)
      if (std::find(l.notes.begin(), l.notes.end(), n) == l.notes.end()) l.notes.push_back(n);
  // The same image twice (a folder copied into itself) would pass for a second volume.
  std::map<std::string, const DicomFileHeader*> by_sop;
  for (const DicomFileHeader& h : l.group.headers)
    if (!h.sop_uid.empty())
      if (auto [it, fresh] = by_sop.try_emplace(h.sop_uid, &h); !fresh)
        throw Error(original_names(
            l.group, fmt::format("{}: {} and {} are the same image (SOPInstanceUID {})", l.what,
                                 it->second->file.string(), h.file.string(), h.sop_uid)));
  std::vector<DicomFrame> images;
  for (const DicomFileHeader& h : l.group.headers)
    images.insert(images.end(), h.frames.begin(), h.frames.end());
  if (images.size() > 1 &&
      std::none_of(images.begin(), images.end(), [](const DicomFrame& f) { return f.position; }))
    l.notes.push_back(place_without_positions(images, l.group.headers.front()));
  try {
    l.volumes = split_volumes(std::move(images), l.what);
  } catch (const Error& e) {
    throw Error(original_names(l.group, e.what()));
  }
  return l;
}

// Everything but the pixels of volume `frame`.
AcquiredSeries acquired_layout(const SeriesLayout& l, int frame) {
  AcquiredSeries out;
  out.info = l.group.info;
  if (!l.note.empty()) out.notes.push_back(l.note);
  out.notes.insert(out.notes.end(), l.notes.begin(), l.notes.end());
  out.notes.insert(out.notes.end(), l.volumes.notes.begin(), l.volumes.notes.end());
  const DicomFileHeader& first = l.group.headers.front();
  out.modality = first.modality;
  out.photometric = first.photometric;
  out.rescale_type = first.rescale_type;
  out.suv = first.suv;
  out.frames = static_cast<int>(l.volumes.volumes.size());
  out.labels = l.volumes.labels;
  const std::vector<DicomFrame>& images = l.volumes.volumes[static_cast<size_t>(frame)];
  std::optional<double> thickness = first.slice_spacing;
  if (images.size() == 1 && !thickness) {
    if (!first.slice_spacing_fault.empty()) throw Error(first.slice_spacing_fault);
    thickness = 1.0;
    out.notes.push_back(
        "no SpacingBetweenSlices (0018,0088) or SliceThickness (0018,0050): the single slice is "
        "placed 1 mm thick");
  }
  try {
    out.stack = order_slices(images, first.rows, first.columns, thickness, l.what);
  } catch (const Error& e) {
    // A slice cut too short to be known as DICOM leaves a gap: name what was passed over.
    if (l.not_images.empty()) throw;
    std::string names;
    for (size_t i = 0; i < std::min<size_t>(3, l.not_images.size()); ++i)
      names += (i > 0 ? ", " : "") + l.not_images[i];
    const bool one = l.not_images.size() == 1;
    throw Error(
        fmt::format("{} ({} passed over: {}{})", e.what(),
                    one ? std::string("1 file in the folder is not a DICOM image and was")
                        : fmt::format("{} files in the folder are not DICOM images and were",
                                      l.not_images.size()),
                    names, l.not_images.size() > 3 ? ", ..." : ""));
  }
  if (first.mosaic_tiles > 0)
    out.notes.push_back(fmt::format("Siemens mosaic: {} tiles of {}x{} per file",
                                    first.mosaic_tiles, first.columns, first.rows));
  if (out.photometric == "MONOCHROME1")
    out.notes.push_back("MONOCHROME1: low values display bright; the values are kept as stored");
  return out;
}

std::vector<AcquiredSeries> decode_volumes(const SeriesLayout& l, std::vector<int> which,
                                           bool stored_values);

}  // namespace

AcquiredSeries read_series_layout(const std::filesystem::path& source, const std::string& series,
                                  int frame) {
  SeriesLayout l = layout_of(source, series);
  require_frame(frame, static_cast<int>(l.volumes.volumes.size()), l.what);
  try {
    return acquired_layout(l, frame);
  } catch (const Error& e) {
    throw Error(original_names(l.group, e.what()));
  }
}

std::vector<AcquiredSeries> read_acquired_volumes(const std::filesystem::path& source,
                                                  const std::string& series, std::vector<int> which,
                                                  bool stored_values) {
  SeriesLayout l = layout_of(source, series);
  try {
    return decode_volumes(l, std::move(which), stored_values);
  } catch (const Error& e) {
    throw Error(original_names(l.group, e.what()));
  }
}

namespace {}  // namespace

std::shared_ptr<std::byte[]> voxel_memory(size_t bytes) {
  // Large buffers in 2 MiB pages where the kernel gives them (transparent huge pages on
  // request): one page fault per 2 MiB instead of one per 4 KiB.
  constexpr size_t kHuge = size_t{2} << 20;
  if (bytes < kHuge) return std::shared_ptr<std::byte[]>(new std::byte[bytes]);
  const size_t rounded = (bytes + kHuge - 1) / kHuge * kHuge;
  void* p = std::aligned_alloc(kHuge, rounded);
  if (p == nullptr) throw std::bad_alloc();
  ::madvise(p, rounded, MADV_HUGEPAGE);
  return std::shared_ptr<std::byte[]>(static_cast<std::byte*>(p),
                                      [](std::byte* q) { std::free(q); });
}

namespace {

// Where an image of a file goes: (image index in file, volume, slice).
struct Slot {
  int image;
  size_t volume, slice;
};
using SlotsByFile = std::map<std::filesystem::path, std::vector<Slot>>;

// Reads every needed file's stored values straight into its volume's slices, when all are native
// integers of one type and size (read_stored_images); false, with nothing kept, for any other
// series or a file that could not be read so: the caller then decodes them all into float planes,
// and says what is wrong with any of them in its own words.
bool read_stored_volumes(const std::vector<const DicomFileHeader*>& needed,
                         const SlotsByFile& slots, std::vector<AcquiredSeries>& out) {
  if (needed.empty()) return false;
  const DicomFileHeader& first = *needed.front();
  const std::optional<StoredType> type = native_stored_type(first);
  if (!type) return false;
  for (const DicomFileHeader* h : needed)
    if (native_stored_type(*h) != type || h->rows != first.rows || h->columns != first.columns)
      return false;
  const size_t plane = static_cast<size_t>(first.rows) * first.columns;
  const size_t bytes = plane * stored_size(*type);
  // One buffer for every volume (a 4-D series of small volumes in huge pages too), not zeroed:
  // every slice is read over whole.
  size_t slices = 0;
  for (const AcquiredSeries& a : out) slices += a.stack.frames.size();
  const std::shared_ptr<std::byte[]> all = voxel_memory(bytes * slices);
  size_t at = 0;
  for (AcquiredSeries& a : out) {
    a.stored.type = *type;
    a.stored.ranges.assign(a.stack.frames.size(), StoredRange{});
    a.stored.bytes = std::shared_ptr<std::byte[]>(all, all.get() + at);
    at += bytes * a.stack.frames.size();
  }
  std::atomic<bool> all_read{true};
  tbb::parallel_for(size_t{0}, needed.size(), [&](size_t i) {
    const DicomFileHeader& h = *needed[i];
    std::vector<std::byte*> images(static_cast<size_t>(std::max(h.frame_count, 0)), nullptr);
    std::vector<StoredRange> ranges(images.size());
    for (const Slot& s : slots.at(h.file))
      if (static_cast<size_t>(s.image) < images.size())
        images[static_cast<size_t>(s.image)] = out[s.volume].stored.bytes.get() + s.slice * bytes;
    if (!read_stored_images(h, images, ranges)) {
      all_read = false;
      return;
    }
    for (const Slot& s : slots.at(h.file))
      if (static_cast<size_t>(s.image) < images.size())
        out[s.volume].stored.ranges[s.slice] = ranges[static_cast<size_t>(s.image)];
  });
  if (!all_read)
    for (AcquiredSeries& a : out) a.stored = StoredSlices{};
  return all_read;
}

// Decodes every needed file (through the codecs where it needs them) into float planes; true
// when every file's stored values are integers.
bool decode_float_planes(const std::vector<const DicomFileHeader*>& needed,
                         const SlotsByFile& slots, std::vector<AcquiredSeries>& out) {
  for (AcquiredSeries& a : out) {
    a.values.resize(a.stack.frames.size());
    if (!needed.empty() && is_rgb_image(*needed.front())) a.colours.resize(a.stack.frames.size());
  }
  // Files decode independently (one GDCM reader each), into distinct slices.
  // Compressed files first, in a few decoder processes (dicom_pixels.hpp).
  std::vector<const DicomFileHeader*> compressed;
  std::map<const DicomFileHeader*, size_t> codec_index;
  for (const DicomFileHeader* h : needed)
    if (needs_codec(*h)) {
      codec_index[h] = compressed.size();
      compressed.push_back(h);
    }
  std::vector<CodecPixels> codec_pixels = decode_with_codecs(compressed);
  std::vector<char> integer_pixels(needed.size(), 1);
  tbb::parallel_for(size_t{0}, needed.size(), [&](size_t i) {
    const DicomFileHeader& h = *needed[i];
    const auto it = codec_index.find(&h);
    CodecPixels* codec = it == codec_index.end() ? nullptr : &codec_pixels[it->second];
    DecodedFrames decoded = decode_dicom_frames(h, codec);
    if (codec != nullptr) std::vector<char>().swap(codec->bytes);  // done with them
    integer_pixels[i] = decoded.integer_pixels;
    for (const Slot& s : slots.at(h.file)) {
      out[s.volume].values[s.slice] = std::move(decoded.frames[static_cast<size_t>(s.image)]);
      if (!decoded.colours.empty())
        out[s.volume].colours[s.slice] = std::move(decoded.colours[static_cast<size_t>(s.image)]);
    }
  });
  // A series mixing RGB and greyscale images is two series (dicom_series.cpp keys on samples).
  for (AcquiredSeries& a : out)
    if (std::any_of(a.colours.begin(), a.colours.end(), [](const auto& c) { return c.empty(); }))
      a.colours.clear();
  return std::all_of(integer_pixels.begin(), integer_pixels.end(), [](char c) { return c != 0; });
}

std::vector<AcquiredSeries> decode_volumes(const SeriesLayout& l, std::vector<int> which,
                                           bool stored_values) {
  const int frames = static_cast<int>(l.volumes.volumes.size());
  if (which.empty())
    for (int f = 0; f < frames; ++f) which.push_back(f);
  for (int f : which) require_frame(f, frames, l.what);
  const DicomFileHeader& first = l.group.headers.front();
  const size_t plane = static_cast<size_t>(first.rows) * first.columns;
  check_memory(
      plane * l.volumes.volumes.front().size() * which.size() * sizeof(float),
      fmt::format("{} ({}x{}x{} voxels, {} frame{})", l.what, first.columns, first.rows,
                  l.volumes.volumes.front().size(), which.size(), which.size() == 1 ? "" : "s"));
  std::vector<AcquiredSeries> out;
  for (int f : which) {
    out.push_back(acquired_layout(l, f));
    // The series' file list and labels are the same for every volume: the first alone keeps
    // them, so that thousands of files in hundreds of volumes are not held once per volume.
    if (out.size() > 1) {
      std::vector<std::filesystem::path>().swap(out.back().info.files);
      std::vector<FrameLabel>().swap(out.back().labels);
    }
  }

  // Where each image goes.
  SlotsByFile slots;
  for (size_t v = 0; v < out.size(); ++v) {
    for (size_t s = 0; s < out[v].stack.frames.size(); ++s)
      slots[out[v].stack.frames[s].file].push_back({out[v].stack.frames[s].frame, v, s});
  }
  std::vector<const DicomFileHeader*> needed;
  for (const DicomFileHeader& h : l.group.headers)
    if (slots.count(h.file)) needed.push_back(&h);
  // Stored values are integers; decoded ones are when every file's are.
  const bool integers = (stored_values && read_stored_volumes(needed, slots, out)) ||
                        decode_float_planes(needed, slots, out);
  for (AcquiredSeries& a : out) {
    a.integer_valued = integers;
    const double slope = a.stack.frames.front().slope;
    for (const DicomFrame& f : a.stack.frames)
      if (f.slope != slope || f.slope != std::round(f.slope) ||
          f.intercept != std::round(f.intercept))
        a.integer_valued = false;
  }
  return out;
}

}  // namespace

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

// An RGB series' colours on the volume's grid: each slice's, or the blend of two acquired slices'
// bytes where the grid is resampled (as fill blends their luminance).
std::shared_ptr<const ColourVoxels> colours_on_grid(const detail::AcquiredSeries& a,
                                                    const detail::SliceGrid& grid) {
  const size_t plane = 3 * a.values.front().size();
  auto out = std::make_shared<ColourVoxels>();
  out->rgb.resize(plane * grid.blends.size());
  tbb::parallel_for(size_t{0}, grid.blends.size(), [&](size_t k) {
    const detail::SliceBlend b = grid.blends[k];
    const size_t lower = static_cast<size_t>(b.lower);
    const std::vector<uint8_t>& lo = a.colours[lower];
    const std::vector<uint8_t>& hi = a.colours[std::min(lower + 1, a.colours.size() - 1)];
    uint8_t* dst = out->rgb.data() + k * plane;
    const double w = b.weight;
    for (size_t i = 0; i < plane; ++i)
      dst[i] = w == 0.0 ? lo[i] : static_cast<uint8_t>(std::lround((1.0 - w) * lo[i] + w * hi[i]));
  });
  return out;
}

// The rescaled value of a stored one, computed as decode_dicom_frames computes it (double, then
// float), so that a volume read from stored values equals one read through float planes.
template <class S>
float rescaled(S stored, double slope, double intercept) {
  return static_cast<float>(static_cast<double>(stored) * slope + intercept);
}

// The rescaled values of sorted frame `s`, as decode_dicom_frames would have given them.
template <class S>
void stored_to_floats(const detail::AcquiredSeries& a, size_t s, size_t plane, float* dst) {
  const S* src = reinterpret_cast<const S*>(a.stored.bytes.get()) + s * plane;
  const detail::DicomFrame& f = a.stack.frames[s];
  for (size_t i = 0; i < plane; ++i) dst[i] = rescaled(src[i], f.slope, f.intercept);
}

template <class F>
void with_stored_type(detail::StoredType type, F&& f) {
  switch (type) {
    case detail::StoredType::u8:
      return f(uint8_t{});
    case detail::StoredType::i8:
      return f(int8_t{});
    case detail::StoredType::u16:
      return f(uint16_t{});
    case detail::StoredType::i16:
      return f(int16_t{});
    case detail::StoredType::u32:
      return f(uint32_t{});
    case detail::StoredType::i32:
      return f(int32_t{});
    default:
      throw Error("stored values of a floating-point type");  // read_stored_images reads none
  }
}

// Float planes of the stored values, for a volume that blends slices or scales values (fill).
void stored_to_float_planes(detail::AcquiredSeries& a, size_t plane) {
  a.values.resize(a.stack.frames.size());
  with_stored_type(a.stored.type, [&](auto stored) {
    using S = decltype(stored);
    tbb::parallel_for(size_t{0}, a.values.size(), [&](size_t s) {
      a.values[s].resize(plane);
      stored_to_floats<S>(a, s, plane, a.values[s].data());
    });
  });
  a.stored = detail::StoredSlices{};
}

// The voxels of a volume on the acquired slices (no blend, no scale) in type T, straight from the
// stored values: rescaled in place where T is an integer type of the stored size, else into a new
// buffer; either way not a float plane between, nor a zeroed buffer.
template <class T>
VoxelStorage stored_voxels(const detail::AcquiredSeries& a, size_t plane) {
  const size_t slices = a.stack.frames.size(), count = plane * slices;
  VoxelStorage out;
  with_stored_type(a.stored.type, [&](auto stored) {
    using S = decltype(stored);
    std::shared_ptr<std::byte[]> owner = a.stored.bytes;
    if (sizeof(S) != sizeof(T) || !std::is_integral_v<T>)
      owner = detail::voxel_memory(count * sizeof(T));
    const std::byte* src_bytes = a.stored.bytes.get();
    std::byte* dst_bytes = owner.get();
    tbb::parallel_for(size_t{0}, slices, [&](size_t s) {
      const detail::DicomFrame& f = a.stack.frames[s];
      const std::byte* src = src_bytes + s * plane * sizeof(S);
      std::byte* dst = dst_bytes + s * plane * sizeof(T);
      // memcpy loads and stores: the source and destination may be the same bytes.
      for (size_t i = 0; i < plane; ++i) {
        S v;
        std::memcpy(&v, src + i * sizeof(S), sizeof(S));
        const T t = static_cast<T>(rescaled(v, f.slope, f.intercept));
        std::memcpy(dst + i * sizeof(T), &t, sizeof(T));
      }
    });
    out = VoxelBuffer<T>::view(reinterpret_cast<const T*>(dst_bytes), count,
                               std::shared_ptr<const void>(owner, owner.get()));
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

std::vector<DicomSeriesInfo> list_dicom_series(const std::filesystem::path& source,
                                               std::vector<std::string>* refused) {
  std::vector<DicomSeriesInfo> out;
  for (detail::DicomSeriesGroup& g : detail::scan_dicom_series(source, refused)) {
    // Compressed pixels are corrupt only as a decoder sees them: decode those to list them too.
    if (refused != nullptr) {
      std::vector<const detail::DicomFileHeader*> headers;
      for (const detail::DicomFileHeader& h : g.headers) headers.push_back(&h);
      for (std::string& failure : detail::codec_failures(headers))
        refused->push_back(detail::original_names(g, std::move(failure)));
    }
    out.push_back(std::move(g.info));
  }
  return out;
}

namespace {

// One acquired volume on its even grid, in its storage type, with the series' units and notes.
DicomVolume to_volume(detail::AcquiredSeries& a, const DicomReadOptions& options,
                      const std::string& what) {
  const std::string series_what = fmt::format("{} (series {})", what, a.info.id);
  detail::SliceGrid grid = detail::plan_slice_grid(a.stack, options.slice_spacing_mm, series_what);

  DicomVolume out;
  out.series = std::move(a.info);
  out.notes = a.notes;
  out.notes.insert(out.notes.end(), a.stack.notes.begin(), a.stack.notes.end());
  out.frames = a.frames;
  out.frame_labels = std::move(a.labels);
  if (const auto& tr = a.stack.frames.front().repetition_time_ms) out.repetition_time_s = *tr / 1e3;
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
  // Stored values go straight into the volume's type only where slices keep their values.
  if (a.stored.bytes && (grid.resampled || scale != 1.0)) stored_to_float_planes(a, plane);
  const bool from_stored = a.stored.bytes != nullptr;
  std::vector<std::pair<float, float>> ranges(a.stack.frames.size());
  if (from_stored) {
    // Rescaling is monotonic, as is rounding to float: the stored range's ends give the range.
    for (size_t s = 0; s < ranges.size(); ++s) {
      const detail::DicomFrame& f = a.stack.frames[s];
      const float x = rescaled(a.stored.ranges[s].lo, f.slope, f.intercept),
                  y = rescaled(a.stored.ranges[s].hi, f.slope, f.intercept);
      // The decoder's finiteness check is not on this path: the range's ends stand for it.
      if (!std::isfinite(x) || !std::isfinite(y))
        throw Error(fmt::format(
            "{}: RescaleSlope (0028,1053) {:g} and RescaleIntercept (0028,1052) {:g} make its "
            "stored values {}..{} {:g}..{:g}, beyond what a float holds",
            f.file.string(), f.slope, f.intercept, a.stored.ranges[s].lo, a.stored.ranges[s].hi,
            static_cast<double>(f.slope) * a.stored.ranges[s].lo + f.intercept,
            static_cast<double>(f.slope) * a.stored.ranges[s].hi + f.intercept));
      ranges[s] = {std::min(x, y), std::max(x, y)};
    }
  } else {
    tbb::parallel_for(size_t{0}, a.values.size(),
                      [&](size_t s) { ranges[s] = plane_range(a.values[s]); });
  }
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
  if (from_stored) {
    switch (type) {
      case VoxelType::u8:
        v.voxels = stored_voxels<uint8_t>(a, plane);
        break;
      case VoxelType::i16:
        v.voxels = stored_voxels<int16_t>(a, plane);
        break;
      case VoxelType::u16:
        v.voxels = stored_voxels<uint16_t>(a, plane);
        break;
      case VoxelType::f32:
        v.voxels = stored_voxels<float>(a, plane);
        break;
    }
  } else {
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
  }
  if (!a.colours.empty()) v.colours = colours_on_grid(a, grid);
  out.series.slices = static_cast<int>(a.stack.frames.size());
  v.validate(series_what);
  return out;
}

void check_units(const DicomReadOptions& options, const std::string& what) {
  if (!options.units.empty() && options.units != "suv")
    throw Error(
        fmt::format("{}: units '{}' is not known (give \"suv\" or nothing)", what, options.units));
}

}  // namespace

DicomVolume read_dicom(const std::filesystem::path& source, const DicomReadOptions& options) {
  const std::string what = source.string();
  check_units(options, what);
  std::vector<detail::AcquiredSeries> a =
      detail::read_acquired_volumes(source, options.series, {options.frame}, true);
  DicomVolume out = to_volume(a.front(), options, what);
  if (out.frames > 1) {
    const std::string& label = out.frame_labels[static_cast<size_t>(options.frame)].text;
    out.notes.push_back(fmt::format("frame {} of {}{}", options.frame, out.frames,
                                    label.empty() ? "" : " (" + label + ")"));
  }
  return out;
}

std::vector<DicomVolume> read_dicom_frames(const std::filesystem::path& source,
                                           const DicomReadOptions& options) {
  const std::string what = source.string();
  check_units(options, what);
  std::vector<detail::AcquiredSeries> all =
      detail::read_acquired_volumes(source, options.series, {}, true);
  std::vector<DicomVolume> out;
  for (detail::AcquiredSeries& a : all) {
    out.push_back(to_volume(a, options, what));
    a.values.clear();  // its voxels now live in out's volume
    a.values.shrink_to_fit();
    a.stored = detail::StoredSlices{};
  }
  return out;
}

bool is_dicom_source(const std::filesystem::path& path) {
  std::error_code ec;
  // A Zarr folder (OME-Zarr image) or a TIFF stack is not a DICOM folder.
  if (std::filesystem::is_directory(path, ec))
    return !detail::is_tiff_folder(path) && !std::filesystem::exists(path / ".zgroup", ec) &&
           !std::filesystem::exists(path / ".zattrs", ec) &&
           !std::filesystem::exists(path / ".zarray", ec) &&
           !std::filesystem::exists(path / "zarr.json", ec);
  const std::string name = lower(path.filename().string());
  if (name == "dicomdir") return true;
  const std::string ext = lower(path.extension().string());
  if (ext == ".dcm" || ext == ".dicom") return true;
  if (name.size() > 7 && name.compare(name.size() - 7, 7, ".dcm.gz") == 0) return true;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream in = try_open_input_stream(path);
  char head[132] = {};
  in.read(head, sizeof head);
  return in.gcount() == 132 && std::memcmp(head + 128, "DICM", 4) == 0;
}

VolumeHeader read_dicom_header(const std::filesystem::path& source,
                               const DicomReadOptions& options) {
  detail::AcquiredSeries a = detail::read_series_layout(source, options.series, options.frame);
  detail::SliceGrid grid =
      detail::plan_slice_grid(a.stack, options.slice_spacing_mm, source.string());
  // The storage type needs the values: float stands for "decided when read".
  return {glm::ivec3(a.stack.columns, a.stack.rows, static_cast<int>(grid.blends.size())),
          VoxelType::f32, grid.index_to_world, a.frames, a.labels};
}

}  // namespace imx
