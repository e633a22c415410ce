#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nifti1.h>

#include "intermix/error.hpp"
#include "io/streams/file_head.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/regular_file.hpp"
#include "io/volume/nifti.hpp"
#include "io/voxels/frame_voxels.hpp"
#include "io/voxels/frames.hpp"
#include "io/voxels/nifti_header.hpp"
#include "io/voxels/raw_voxels.hpp"
#include "volume/colour_grid.hpp"
#include "volume/volume_checks.hpp"

namespace imx::detail {

namespace {

namespace fs = std::filesystem;

bool ends_with(const std::string& s, std::string_view suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The files of an image: one .nii, or the header and the voxels of a .hdr/.img pair.
struct ImageFiles {
  fs::path header, voxels;
  bool pair = false;
  bool voxels_gzipped = false;  // a pair's .img.gz (a single file says so by its content)
  std::string what;             // names the header in messages
  std::string data_what;        // names the voxels
  fs::path spm_mat;             // a pair's X.mat, where SPM kept an Analyze image's placement
};

// `stem` followed by the first of `extensions` that names an existing file, each tried in
// lower case and in upper case (the case of the name given first, as nifticlib does).
std::optional<fs::path> find_sibling(const fs::path& dir, const std::string& stem, bool upper,
                                     const std::vector<std::string>& extensions) {
  for (const std::string& ext : extensions)
    for (bool up : {upper, !upper}) {
      std::string e = ext;
      if (up)
        for (char& c : e) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      std::error_code ec;
      fs::path p = dir / (stem + e);
      if (fs::exists(p, ec)) return p;
    }
  return std::nullopt;
}

ImageFiles image_files(const fs::path& file) {
  const std::string given = file.string();
  const std::string name = file.filename().string();
  const std::string low = lower(name);
  ImageFiles f;
  f.what = f.data_what = given;
  const bool hdr = ends_with(low, ".hdr") || ends_with(low, ".hdr.gz");
  const bool img = ends_with(low, ".img") || ends_with(low, ".img.gz");
  if (!hdr && !img) {
    f.header = f.voxels = file;
    return f;
  }
  f.pair = true;
  const bool gz = ends_with(low, ".gz");
  const size_t ext_at = name.size() - (gz ? 7 : 4);
  const std::string stem = name.substr(0, ext_at);
  const bool upper = std::isupper(static_cast<unsigned char>(name[ext_at + 1])) != 0;
  const fs::path dir = file.parent_path();
  // A gzipped header goes with gzipped voxels first, as nibabel writes them; either is found.
  auto order = [&](const std::string& plain) {
    return gz ? std::vector<std::string>{plain + ".gz", plain}
              : std::vector<std::string>{plain, plain + ".gz"};
  };
  if (hdr) {
    f.header = file;
    std::optional<fs::path> voxels = find_sibling(dir, stem, upper, order(".img"));
    if (!voxels)
      throw FileError(fmt::format("{}: its voxel data {} is missing (the .hdr of a pair needs its "
                                  ".img beside it; {}.img.gz was looked for too)",
                                  given, (dir / (stem + (upper ? ".IMG" : ".img"))).string(), stem),
                      ENOENT);
    f.voxels = *voxels;
    f.data_what = fmt::format("{} (voxel data of {})", f.voxels.string(), given);
  } else {
    f.voxels = file;
    std::optional<fs::path> header = find_sibling(dir, stem, upper, order(".hdr"));
    if (!header)
      throw FileError(fmt::format("{}: its header {} is missing (the .img of a pair needs its "
                                  ".hdr beside it; {}.hdr.gz was looked for too)",
                                  given, (dir / (stem + (upper ? ".HDR" : ".hdr"))).string(), stem),
                      ENOENT);
    f.header = *header;
    f.what = fmt::format("{} (header of {})", f.header.string(), given);
    require_regular_file(f.header, f.what);
  }
  f.voxels_gzipped = ends_with(lower(f.voxels.filename().string()), ".gz");
  if (std::optional<fs::path> mat = find_sibling(dir, stem, upper, {".mat"})) f.spm_mat = *mat;
  return f;
}

// What the header says about the volume and where its voxels are.
struct Layout {
  VolumeHeader header;
  FrameLayout data;
  double slope = 0.0, inter = 0.0;
  // RGB24 (3) or RGBA32 (4): `data` is then a grid of uint8 channels, `channels` times as wide.
  int channels = 0;
  // The scaling changes the voxels (slope 0 means "none"), which are then float32.
  bool scaled() const { return slope != 0.0 && !(slope == 1.0 && inter == 0.0); }
};

// Seconds per unit of pixdim[4] from xyzt_units' time bits, when they name a time unit.
std::optional<double> seconds_per_unit(int xyzt_units) {
  switch (XYZT_TO_TIME(xyzt_units)) {
    case NIFTI_UNITS_SEC:
      return 1.0;
    case NIFTI_UNITS_MSEC:
      return 1e-3;
    case NIFTI_UNITS_USEC:
      return 1e-6;
    default:  // unknown, or Hz, ppm, rad/s: not a time step
      return std::nullopt;
  }
}

// Frame k of a time series starts k * pixdim[4] after the first, when the header gives the
// step and its unit; otherwise (components, Analyze, no unit) the frames have no labels.
std::vector<FrameLabel> time_labels(const NiftiHeader& h, int frames) {
  std::vector<FrameLabel> labels;
  const double step = h.pixdim[4];
  const std::optional<double> unit = seconds_per_unit(h.xyzt_units);
  if (frames < 2 || h.dim[4] != frames || !unit || !std::isfinite(step) || step <= 0.0)
    return labels;
  labels.resize(static_cast<size_t>(frames));
  for (int k = 0; k < frames; ++k) {
    labels[k].time_s = k * step * *unit;
    labels[k].text = describe_frame(labels[k]);
  }
  return labels;
}

// Reads and checks the header of `file` (and finds its voxels).
Layout parse_layout(const fs::path& file) {
  const ImageFiles files = image_files(file);
  const std::string& what = files.what;
  const FileHead head = read_file_head(files.header, 540, what);
  const NiftiHeader h = decode_nifti_header(head.bytes, files.pair, head.gzipped, what);
  // A CIFTI matrix is no grid: read as one it would be a 1x1x1 volume of many frames.
  if (h.intent_code >= 3000 && h.intent_code <= 3099) throw Error(cifti_needs_surfaces(what));
  if (h.kind == NiftiKind::analyze && !files.spm_mat.empty())
    throw Error(fmt::format(
        "{}: SPM's placement file {} lies beside this Analyze 7.5 image; intermix does not read "
        ".mat files, and the header alone would place the image elsewhere (convert it to NIfTI)",
        what, files.spm_mat.string()));

  for (int a = 1; a <= 3; ++a)
    if (h.dim[a] > INT_MAX)
      throw Error(fmt::format("{}: dim[{}] is {}, more than {}", what, a, h.dim[a], INT_MAX));
  const glm::ivec3 dims(static_cast<int>(h.dim[1]), static_cast<int>(h.dim[2]),
                        static_cast<int>(h.dim[3]));
  // In double: three int32 sizes can overflow a uint64 product back into range.
  if (static_cast<double>(dims.x) * dims.y * dims.z > static_cast<double>(kMaxGridVoxels))
    throw Error(fmt::format("{}: dimensions {}x{}x{} give more than {} voxels", what, dims.x,
                            dims.y, dims.z, kMaxGridVoxels));

  // Frames lie along the one dimension beyond the third that is larger than 1: time (dim[4])
  // or components (dim[5], dim[4] being 1), or any other alone. Two such dimensions would need
  // a second frame index: refused rather than flattened.
  int64_t frames = 1;
  int along = 0;
  std::string shape = fmt::format("{}", h.dim[1]);
  for (int d = 2; d <= h.ndim; ++d) shape += fmt::format("x{}", h.dim[d]);
  for (int d = 4; d < 8; ++d) {
    if (h.dim[d] <= 1) continue;
    if (along != 0)
      throw Error(
          fmt::format("{}: dims {}: dim[{}] and dim[{}] are both larger than 1; frames are read "
                      "along one dimension beyond the third (time, dim[4], or components, dim[5])",
                      what, shape, along, d));
    along = d;
    frames = h.dim[d];
  }
  check_frame_count(dims, frames, what);

  Layout l;
  // nifti1.h: scl_slope and scl_inter do not apply to RGB data (nibabel cannot apply them).
  l.slope = h.colour_channels ? 0.0 : h.slope;
  l.inter = h.colour_channels ? 0.0 : h.inter;
  l.channels = h.colour_channels;
  if (l.channels && dims.x > INT_MAX / l.channels)
    throw Error(fmt::format("{}: dim[1] is {}, more than {} colour voxels a row", what, dims.x,
                            INT_MAX / l.channels));
  l.data.file = files.voxels;
  l.data.what = files.data_what;
  l.data.gzipped = files.pair ? files.voxels_gzipped : head.gzipped;
  l.data.offset = h.vox_offset;
  l.data.type = h.type;
  l.data.swap = h.swapped;
  l.data.dims = l.channels ? glm::ivec3(dims.x * l.channels, dims.y, dims.z) : dims;
  l.data.frames = static_cast<int>(frames);
  l.header.dims = dims;
  l.header.type = l.scaled() ? VoxelType::f32 : storage_type_for(h.type);
  l.header.index_to_world = nifti_index_to_world(h);
  l.header.frames = l.data.frames;
  l.header.frame_labels = time_labels(h, l.data.frames);
  return l;
}

// The voxels of `box` of frame `frame` of a colour image: its luminance (RGB24) or alpha
// (RGBA32, as NiiVue takes its opacity), and its colours into `colours`.
VoxelStorage read_colour_voxels(const Layout& l, int frame, const VoxelBox& box,
                                std::shared_ptr<const ColourVoxels>& colours) {
  const int n = l.channels;
  const VoxelBox bytes{{box.lo.x * n, box.lo.y, box.lo.z}, {box.hi.x * n, box.hi.y, box.hi.z}};
  VoxelStorage raw = read_frame_voxels(l.data, frame, bytes);
  const uint8_t* in = std::get<VoxelBuffer<uint8_t>>(raw).data();
  const size_t count = box.count();
  auto rgb = std::make_shared<ColourVoxels>();
  rgb->rgb.resize(3 * count);
  std::vector<uint8_t> scalar(count);
  for (size_t i = 0; i < count; ++i) {
    const uint8_t* c = in + n * i;
    std::copy(c, c + 3, rgb->rgb.data() + 3 * i);
    scalar[i] = n == 4 ? c[3] : colour_luminance(c[0], c[1], c[2]);
  }
  colours = std::move(rgb);
  return VoxelBuffer<uint8_t>(std::move(scalar));
}

// The voxels of `box` of frame `frame`, scaled.
VoxelStorage read_voxels(const Layout& l, int frame, const VoxelBox& box) {
  VoxelStorage voxels = read_frame_voxels(l.data, frame, box);
  if (!l.scaled()) return voxels;
  return std::visit(
      [&](const auto& src) -> VoxelStorage {
        std::vector<float> out(src.size());
        for (size_t i = 0; i < src.size(); ++i)
          out[i] = static_cast<float>(static_cast<double>(src[i]) * l.slope + l.inter);
        return VoxelBuffer<float>(std::move(out));
      },
      voxels);
}

}  // namespace

VolumeHeader read_nifti_header(const fs::path& file) {
  VolumeHeader header = parse_layout(file).header;
  check_placement(header.index_to_world, file.string());
  return header;
}

VolumeData read_nifti_region(const fs::path& file, const VoxelBox& box, int frame) {
  const Layout layout = parse_layout(file);
  std::shared_ptr<const ColourVoxels> colours;
  VolumeData v = frame_box_volume(
      layout.header, layout.data.frames, frame, box, file.string(), [&](const VoxelBox& b) {
        return layout.channels ? read_colour_voxels(layout, frame, b, colours)
                               : read_voxels(layout, frame, b);
      });
  v.colours = std::move(colours);
  return v;
}

VolumeData read_nifti(const fs::path& file, int frame) {
  return read_nifti_region(file, VoxelBox::whole(parse_layout(file).header.dims), frame);
}

}  // namespace imx::detail
