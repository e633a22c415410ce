// Philips PAR/REC, read as nibabel.parrec reads it (nibabel being the reference the tests compare
// to): the slice table's lines gathered into volumes and placed, the REC's little-endian
// unsigned 8- or 16-bit slices in table order. The PAR text is parsed by parrec_header.cpp.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"
#include "io/volume/parrec.hpp"
#include "io/volume/parrec_header.hpp"
#include "io/voxels/frame_voxels.hpp"
#include "io/voxels/frames.hpp"
#include "io/voxels/raw_voxels.hpp"
#include "volume/volume_checks.hpp"

namespace imx::detail {

namespace {

namespace fs = std::filesystem;

struct Layout {
  VolumeHeader header;
  fs::path rec;
  std::string rec_what;
  int bytes_per_pixel = 2;
  std::vector<size_t> order;             // table line of each (volume, slice), slice fastest
  std::vector<double> slope, intercept;  // per table line
};

// PSL (Philips' patient axes) of the voxel axes for each slice orientation (1 transverse,
// 2 sagittal, 3 coronal), as nibabel's ACQ_TO_PSL: rows P, S, L; columns i, j, k.
glm::dmat3 to_psl(int orientation) {
  glm::dmat3 m(0.0);  // m[column][row]
  auto set = [&](int row, int column, double v) { m[column][row] = v; };
  if (orientation == 1) {
    set(0, 1, 1);
    set(1, 2, 1);
    set(2, 0, 1);
  } else if (orientation == 2) {
    set(0, 0, 1);
    set(1, 1, -1);
    set(2, 2, -1);
  } else {
    set(0, 2, 1);
    set(1, 1, -1);
    set(2, 0, 1);
  }
  return m;
}

glm::dmat3 rotation(int axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  glm::dmat3 m(1.0);  // m[column][row]
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  m[a][a] = c;
  m[b][a] = -s;
  m[a][b] = s;
  m[b][b] = c;
  return m;
}

// nibabel's PARRECHeader.get_affine(origin='scanner'): centre the grid, scale by the voxel sizes,
// permute to PSL, rotate by the angulation (Rz(rl) Rx(ap) Ry(fh), nibabel's order), move by the
// off-centre; then PSL -> LPS (L = PSL's third, P its first, S its second).
glm::dmat4 index_to_lps(glm::ivec3 dims, glm::dvec3 zooms, int orientation,
                        const std::vector<double>& angulation,
                        const std::vector<double>& off_centre) {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  const glm::dmat3 rot = rotation(2, angulation[2] * kDeg) * rotation(0, angulation[0] * kDeg) *
                         rotation(1, angulation[1] * kDeg);
  glm::dmat3 scale(1.0);
  for (int a = 0; a < 3; ++a) scale[a][a] = zooms[a];
  const glm::dmat3 psl = rot * to_psl(orientation) * scale;
  const glm::dvec3 centre = (glm::dvec3(dims) - 1.0) / 2.0;
  const glm::dvec3 origin =
      -(psl * centre) + glm::dvec3(off_centre[0], off_centre[1], off_centre[2]);
  glm::dmat4 lps(1.0);
  for (int c = 0; c < 3; ++c) {
    lps[c][0] = psl[c][2];
    lps[c][1] = psl[c][0];
    lps[c][2] = psl[c][1];
  }
  lps[3] = glm::dvec4(origin[2], origin[0], origin[1], 1.0);
  return lps;
}

// The other file of the pair: the same name with `ext` in the given extension's case, else in
// the other case.
fs::path partner(const fs::path& file, const char* upper, const char* lowercase) {
  const std::string given = file.extension().string();
  const bool is_upper =
      std::any_of(given.begin(), given.end(), [](unsigned char c) { return std::isupper(c) != 0; });
  fs::path first = file, second = file;
  first.replace_extension(is_upper ? upper : lowercase);
  second.replace_extension(is_upper ? lowercase : upper);
  std::error_code ec;
  if (fs::exists(first, ec) || !fs::exists(second, ec)) return first;
  return second;
}

// Frame labels: for each volume, what its first slice's line says, for the properties that
// differ between volumes (b values and directions for a diffusion series, as nibabel's
// get_bvals_bvecs gives them: along the voxel axes).
void label_frames(const ParHeader& par, Layout& l, int orientation, int slices) {
  const int frames = l.header.frames;
  if (frames < 2) return;
  auto first_row = [&](int f) -> const ParRow& {
    return par.rows[l.order[static_cast<size_t>(f) * slices]];
  };
  auto varies = [&](size_t column) {
    for (int f = 1; f < frames; ++f)
      if (first_row(f)[column] != first_row(0)[column]) return true;
    return false;
  };
  const std::vector<double>* diffusion = par_general(par, "diffusion");
  const bool dwi = diffusion != nullptr && diffusion->front() != 0.0;
  const bool has_gradient = par.rows.front().size() > ParColumn::kGradient + 2;
  const bool time = varies(ParColumn::kDynamicStart), echo = varies(ParColumn::kEchoTime),
             trigger = varies(ParColumn::kTriggerTime), type = varies(ParColumn::kImageType);
  if (!dwi && !time && !echo && !trigger && !type) return;
  const glm::dmat3 psl = to_psl(orientation);
  l.header.frame_labels.resize(static_cast<size_t>(frames));
  for (int f = 0; f < frames; ++f) {
    const ParRow& row = first_row(f);
    FrameLabel& label = l.header.frame_labels[static_cast<size_t>(f)];
    if (time) label.time_s = row[ParColumn::kDynamicStart] - first_row(0)[ParColumn::kDynamicStart];
    if (dwi) {
      label.b_value = row[ParColumn::kBFactor];
      // The table's (ap, fh, rl) read as PSL, taken back to the voxel axes.
      if (has_gradient)
        label.b_vector = glm::transpose(psl) * glm::dvec3(row[ParColumn::kGradient],
                                                          row[ParColumn::kGradient + 1],
                                                          row[ParColumn::kGradient + 2]);
    }
    if (echo) label.echo_time_ms = row[ParColumn::kEchoTime];
    if (trigger) label.trigger_time_ms = row[ParColumn::kTriggerTime];
    if (type) {
      static const char* const kTypes[] = {"M", "R", "I", "P"};
      const double t = row[ParColumn::kImageType];
      label.image_type = t >= 0 && t < 4 ? kTypes[static_cast<int>(t)] : fmt::format("type {}", t);
    }
    label.text = describe_frame(label);
  }
}

Layout parse_layout(const fs::path& file) {
  const std::string given = file.string();
  const std::string ext = lower(file.extension().string());
  fs::path par_file, rec_file;
  if (ext == ".par") {
    par_file = file;
    rec_file = partner(file, ".REC", ".rec");
  } else if (ext == ".rec") {
    rec_file = file;
    par_file = partner(file, ".PAR", ".par");
  } else {
    throw Error(fmt::format("{}: a PAR/REC file must be named .PAR or .REC", given));
  }
  const std::string what = par_file.string();
  const ParHeader par = read_par_header(par_file, what);

  // nibabel's vol_numbers and vol_is_full: the n-th line of a slice number belongs to volume n,
  // and every volume must hold each slice 1 .. max_slices.
  const double max_slices =
      require_par_general(par, "max_slices", "Max. number of slices/locations", what).front();
  if (max_slices < 1 || max_slices > static_cast<double>(par.rows.size()))
    throw Error(fmt::format("{}: 'Max. number of slices/locations' is {} for a table of {} lines",
                            what, max_slices, par.rows.size()));
  const int slices = static_cast<int>(max_slices);
  std::vector<std::vector<size_t>> lines_of_slice(static_cast<size_t>(slices));
  for (size_t r = 0; r < par.rows.size(); ++r) {
    const double s = par.rows[r][ParColumn::kSlice];
    if (s < 1 || s > slices)
      throw Error(fmt::format("{}: line {} of the slice table has slice number {}, outside 1 .. {}",
                              what, r + 1, s, slices));
    lines_of_slice[static_cast<size_t>(s) - 1].push_back(r);
  }
  const size_t volumes = lines_of_slice.front().size();
  for (int s = 0; s < slices; ++s)
    if (lines_of_slice[static_cast<size_t>(s)].size() != volumes)
      throw Error(
          fmt::format("{}: slice {} appears {} times and slice 1 {} times: the series has "
                      "one or more partial volumes",
                      what, s + 1, lines_of_slice[static_cast<size_t>(s)].size(), volumes));
  if (static_cast<int64_t>(volumes) > kMaxFrames)
    throw Error(fmt::format("{}: {} volumes is more than {}", what, volumes, kMaxFrames));

  Layout l;
  const double bits = unique_par_value(par, ParColumn::kPixelBits, "image pixel size", what);
  if (bits != 8 && bits != 16)
    throw Error(
        fmt::format("{}: image pixel size is {} bits: only 8 and 16 are supported", what, bits));
  l.bytes_per_pixel = bits == 8 ? 1 : 2;
  const double rx = unique_par_value(par, ParColumn::kReconX, "recon resolution", what);
  const double ry = unique_par_value(par, ParColumn::kReconY, "recon resolution", what);
  if (rx < 1 || ry < 1 || rx * ry * slices > static_cast<double>(kMaxVoxels))
    throw Error(fmt::format("{}: recon resolution {} x {} with {} slices is not a valid grid", what,
                            rx, ry, slices));
  const glm::ivec3 dims(static_cast<int>(rx), static_cast<int>(ry), slices);
  check_frame_count(dims, static_cast<int64_t>(volumes), what);
  const double gap = unique_par_value(par, ParColumn::kGap, "slice gap", what);
  const double sx = unique_par_value(par, ParColumn::kSpacingX, "pixel spacing", what);
  const double sy = unique_par_value(par, ParColumn::kSpacingY, "pixel spacing", what);
  const double thickness = unique_par_value(par, ParColumn::kThickness, "slice thickness", what);
  if (volumes > 1) {
    // nibabel reads the TR for a dynamic series' fourth zoom, and refuses a header without it.
    const double dynamic = require_par_general(par, "dyn_scan", "Dynamic scan", what).front();
    if (dynamic != 0 &&
        require_par_general(par, "repetition_time", "Repetition time [ms]", what).empty())
      throw Error(fmt::format("{}: 'Repetition time' holds no number", what));
  }

  // The REC holds every line's slice in table order, whatever the table's "index in REC file".
  l.rec = rec_file;
  l.rec_what = fmt::format("{} (REC data of {})", rec_file.string(), what);
  require_regular_file(rec_file, l.rec_what);
  std::error_code ec;
  const uintmax_t rec_size = fs::file_size(rec_file, ec);
  if (ec) throw FileError(fmt::format("{}: cannot read its size", l.rec_what), ec.value());
  const uintmax_t needed = static_cast<uintmax_t>(rx) * static_cast<uintmax_t>(ry) *
                           par.rows.size() * static_cast<uintmax_t>(l.bytes_per_pixel);
  if (rec_size < needed)
    throw Error(
        fmt::format("{}: holds {} bytes, but the PAR's {} slices of {} x {} {}-bit pixels "
                    "need {}",
                    l.rec_what, rec_size, par.rows.size(), rx, ry, bits, needed));

  const double orientation =
      unique_par_value(par, ParColumn::kOrientation, "slice orientation", what);
  if (orientation != 1 && orientation != 2 && orientation != 3)
    throw Error(
        fmt::format("{}: slice orientation {} is not 1 (transverse), 2 (sagittal) or 3 "
                    "(coronal)",
                    what, orientation));
  const std::vector<double>& angulation =
      require_par_general(par, "angulation", "Angulation midslice(ap,fh,rl)[degr]", what);
  const std::vector<double>& off_centre =
      require_par_general(par, "off_center", "Off Centre midslice(ap,fh,rl) [mm]", what);

  l.order.reserve(volumes * static_cast<size_t>(slices));
  for (size_t v = 0; v < volumes; ++v)
    for (int s = 0; s < slices; ++s) l.order.push_back(lines_of_slice[static_cast<size_t>(s)][v]);
  for (const ParRow& row : par.rows) {
    l.slope.push_back(row[ParColumn::kRescaleSlope]);
    l.intercept.push_back(row[ParColumn::kRescaleIntercept]);
  }
  l.header.dims = dims;
  l.header.type = VoxelType::f32;
  l.header.frames = static_cast<int>(volumes);
  l.header.index_to_world = index_to_lps(dims, glm::dvec3(sx, sy, thickness + gap),
                                         static_cast<int>(orientation), angulation, off_centre);
  label_frames(par, l, static_cast<int>(orientation), slices);
  return l;
}

// The box of frame `frame`, slice by slice: each slice's rows of the box in one read, scaled by
// that slice's rescale slope and intercept.
VoxelStorage read_box(const Layout& l, int frame, const VoxelBox& box) {
  const glm::ivec3 dims = l.header.dims, size = box.size();
  std::ifstream in = open_input_stream(l.rec, l.rec_what);
  const uint64_t slice_bytes = static_cast<uint64_t>(dims.x) * dims.y * l.bytes_per_pixel;
  const size_t row_bytes = static_cast<size_t>(dims.x) * l.bytes_per_pixel;
  std::vector<uint8_t> rows(row_bytes * static_cast<size_t>(size.y));
  return load_voxels(RawType::f32, box.count(), false, l.rec_what, [&](std::span<uint8_t> out) {
    float* voxels = reinterpret_cast<float*>(out.data());
    for (int k = box.lo.z; k < box.hi.z; ++k) {
      const size_t line = l.order[static_cast<size_t>(frame) * dims.z + k];
      in.seekg(static_cast<std::streamoff>(line * slice_bytes + box.lo.y * row_bytes));
      in.read(reinterpret_cast<char*>(rows.data()), static_cast<std::streamsize>(rows.size()));
      if (!in)
        throw Error(fmt::format("{}: ends within slice {} (the file shrank while read)", l.rec_what,
                                line + 1));
      const double slope = l.slope[line], intercept = l.intercept[line];
      for (int j = 0; j < size.y; ++j)
        for (int i = 0; i < size.x; ++i) {
          const size_t at = static_cast<size_t>(j) * dims.x + box.lo.x + i;
          const double raw = l.bytes_per_pixel == 1
                                 ? rows[at]
                                 : static_cast<double>(rows[2 * at] | (rows[2 * at + 1] << 8));
          *voxels++ = static_cast<float>(raw * slope + intercept);
        }
    }
  });
}

}  // namespace

VolumeHeader read_parrec_header(const std::filesystem::path& file) {
  VolumeHeader header = parse_layout(file).header;
  check_placement(header.index_to_world, file.string());
  return header;
}

VolumeData read_parrec_region(const std::filesystem::path& file, const VoxelBox& box, int frame) {
  const Layout l = parse_layout(file);
  return frame_box_volume(l.header, l.header.frames, frame, box, file.string(),
                          [&](const VoxelBox& b) { return read_box(l, frame, b); });
}

VolumeData read_parrec(const std::filesystem::path& file, int frame) {
  const Layout l = parse_layout(file);
  return frame_box_volume(l.header, l.header.frames, frame, VoxelBox::whole(l.header.dims),
                          file.string(), [&](const VoxelBox& b) { return read_box(l, frame, b); });
}

}  // namespace imx::detail
