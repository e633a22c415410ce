// intermix convert IN -o OUT: any volume intermix reads (a DICOM series too), written as
// NIfTI, NRRD or MetaImage, so its geometry can be checked in another tool. A multi-frame (4-D)
// source becomes a 4-D NIfTI as dcm2niix writes it, with .bval/.bvec for diffusion and a JSON
// sidecar of the frame labels; --frame K writes one frame. An output ending in .zarr is an
// OME-Zarr pyramid, written slab by slab, so that a volume larger than memory converts too.
#include <cstdio>
#include <optional>
#include <variant>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "core/progress_bar.hpp"
#include "intermix/dicom.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/streams/atomic_file.hpp"
#include "io/voxels/raw_voxels.hpp"
#include "io/zarr/ome_zarr_writer.hpp"

namespace imx::cli {

namespace {

// Where the sidecars go: OUT without .nii.gz / .nii, plus the extension.
std::string sidecar(const std::string& output, const std::string& extension) {
  for (const char* ext : {".nii.gz", ".nii"}) {
    const std::string e = ext;
    if (output.size() > e.size() && output.compare(output.size() - e.size(), e.size(), e) == 0)
      return output.substr(0, output.size() - e.size()) + extension;
  }
  return output + extension;
}

// The storage type that holds every frame's values exactly: frames of one series may differ
// (a b = 0 volume fits u8 where the others need i16).
VoxelType common_type(const std::vector<VolumeData>& frames) {
  bool u8 = true, i16 = true, u16 = true;
  for (const VolumeData& f : frames) {
    const VoxelType t = f.type();
    u8 = u8 && t == VoxelType::u8;
    i16 = i16 && (t == VoxelType::u8 || t == VoxelType::i16);
    u16 = u16 && (t == VoxelType::u8 || t == VoxelType::u16);
  }
  return u8 ? VoxelType::u8 : i16 ? VoxelType::i16 : u16 ? VoxelType::u16 : VoxelType::f32;
}

template <class T>
VoxelStorage converted(const VolumeData& v) {
  std::vector<T> out(v.voxel_count());
  std::visit(
      [&](const auto& src) {
        for (size_t i = 0; i < out.size(); ++i) out[i] = static_cast<T>(src[i]);
      },
      v.voxels);
  return VoxelBuffer<T>(std::move(out));
}

void convert_to(VolumeData& v, VoxelType type) {
  if (v.type() == type) return;
  switch (type) {
    case VoxelType::u8:
      v.voxels = converted<uint8_t>(v);
      break;
    case VoxelType::i16:
      v.voxels = converted<int16_t>(v);
      break;
    case VoxelType::u16:
      v.voxels = converted<uint16_t>(v);
      break;
    case VoxelType::f32:
      v.voxels = converted<float>(v);
      break;
  }
}

// FSL's (and dcm2niix's) .bvec: components along the written image's voxel axes, x negated when
// the affine's determinant is positive. Labels hold them along the volume's i, j, k axes.
void write_diffusion(const std::vector<FrameLabel>& labels, const glm::dmat4& index_to_world,
                     const std::string& output) {
  const bool flip_x = glm::determinant(glm::dmat3(index_to_world)) > 0.0;
  std::string bval, bvec[3];
  for (const FrameLabel& l : labels) {
    const glm::dvec3 v = l.b_vector.value_or(glm::dvec3(0.0));
    bval += fmt::format("{}{:.6g}", bval.empty() ? "" : " ", l.b_value.value_or(0.0));
    for (int a = 0; a < 3; ++a)
      bvec[a] += fmt::format("{}{:.6g}", bvec[a].empty() ? "" : " ",
                             (a == 0 && flip_x ? -v[a] : v[a]) + 0.0);
  }
  write_file_atomically(sidecar(output, ".bval"), [&](std::ostream& out) { out << bval << "\n"; });
  write_file_atomically(sidecar(output, ".bvec"), [&](std::ostream& out) {
    out << bvec[0] << "\n" << bvec[1] << "\n" << bvec[2] << "\n";
  });
}

void write_frame_labels(const std::vector<FrameLabel>& labels, const std::string& output) {
  nlohmann::json frames = nlohmann::json::array();
  for (const FrameLabel& l : labels) {
    nlohmann::json j = {{"label", l.text}};
    if (l.time_s) j["time_s"] = *l.time_s;
    if (l.b_value) j["b_value"] = *l.b_value;
    if (l.b_vector) j["b_vector_ijk"] = {l.b_vector->x, l.b_vector->y, l.b_vector->z};
    if (l.echo_time_ms) j["echo_time_ms"] = *l.echo_time_ms;
    if (l.trigger_time_ms) j["trigger_time_ms"] = *l.trigger_time_ms;
    if (!l.image_type.empty()) j["image_type"] = l.image_type;
    frames.push_back(j);
  }
  write_file_atomically(sidecar(output, ".json"), [&](std::ostream& out) {
    out << nlohmann::json{{"frames", frames}}.dump(1, '\t') << "\n";
  });
}

// Seconds between time points from the labels' acquisition times (the first step).
double frame_seconds(const std::vector<FrameLabel>& labels) {
  if (labels.size() < 2 || !labels[0].time_s || !labels[1].time_s) return 0.0;
  return std::max(0.0, *labels[1].time_s - *labels[0].time_s);
}

bool is_nifti(const std::string& output) {
  return sidecar(output, "") != output;
}

// IN -o OUT.zarr: one frame of a volume as an OME-Zarr pyramid. A volume one process can hold is
// read once; a larger one slab by slab, by region.
void write_pyramid(const std::string& input, const std::string& output, int frame, int chunk,
                   const DicomReadOptions* dicom) {
  std::error_code ec;
  if (std::filesystem::equivalent(input, output, ec))
    throw Error(fmt::format("{}: is the input; name another output", output));
  VolumeHeader header;
  std::shared_ptr<const VolumeData> whole;
  if (dicom) {
    DicomVolume d = read_dicom(input, *dicom);
    print_notes(d.notes);
    whole = std::make_shared<VolumeData>(std::move(d.volume));
  } else {
    header = read_volume_header(input);
    if (frame >= header.frames)
      throw Error(
          fmt::format("{}: frame {} requested, the file has {}", input, frame, header.frames));
    if (header.frames > 1 && !quiet())
      std::fprintf(stderr, "intermix: note: %s: frame %d of %d (name another with --frame K)\n",
                   input.c_str(), frame, header.frames);
    try {
      detail::require_holdable(header, input);
      whole = std::make_shared<VolumeData>(read_volume(input, frame));
    } catch (const VolumeTooLarge&) {  // read slab by slab below
    }
  }
  if (whole) header = {whole->dims, whole->type(), whole->index_to_world, 1, {}};
  const auto read_box = [&](const VoxelBox& box) {
    return whole ? crop(*whole, box, input) : read_volume_region(input, box, frame);
  };
  ProgressBar bar("convert", show_progress());
  detail::OmeZarrWriteOptions options;
  options.chunk = chunk;
  options.progress = [&bar](double f) { bar.update(f); };
  detail::write_ome_zarr(header, read_box, output, options);
  bar.finish();
  if (!quiet())
    std::fprintf(stderr, "intermix: %s %dx%dx%d %s -> %s (%d levels, %d^3 chunks)\n", input.c_str(),
                 header.dims.x, header.dims.y, header.dims.z, voxel_type_name(header.type),
                 output.c_str(), detail::ome_zarr_level_count(header.dims, chunk), chunk);
}

}  // namespace

Command add_convert(CLI::App& app) {
  struct Options {
    std::string input, output, series, units;
    std::optional<double> slice_spacing;
    std::optional<int> frame;
    bool raw = false;
    int chunk = 64;
  };
  auto o = std::make_shared<Options>();
  app.add_option("input", o->input,
                 "volume file (.nrrd, .nhdr, .nii, .nii.gz, .hdr/.img, .mgh, .mgz, .mha, .mhd), "
                 "DICOM file, DICOMDIR or folder")
      ->required();
  app.add_option("-o,--output", o->output,
                 "output file: .nii.gz, .nii, .nrrd or .mha; or a folder .zarr (an OME-Zarr "
                 "pyramid, for volumes larger than memory)")
      ->required();
  app.add_option("--series", o->series, "DICOM: the series number or SeriesInstanceUID");
  app.add_option("--units", o->units, "DICOM PET: 'suv' for standardized uptake values")
      ->check(CLI::IsMember({"suv"}));
  app.add_option("--slice-spacing", o->slice_spacing,
                 "DICOM with uneven slice gaps: resample at this spacing in mm (default: the "
                 "smallest gap)")
      ->check(in_range(1e-3, 1e3));
  app.add_option("--frame", o->frame,
                 "of a multi-frame (4-D) source: write only this frame (0-based); default: all, "
                 "as a 4-D NIfTI")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--raw", o->raw, "write uncompressed voxels (NRRD, MetaImage)");
  app.add_option("--chunk", o->chunk, "OME-Zarr: chunk edge in voxels (default: 64)")
      ->check(CLI::Range(8, 512));
  return [o]() {
    if (o->output.ends_with(".zarr")) {
      const bool dicom = is_dicom_source(o->input);
      if (!dicom && (!o->series.empty() || !o->units.empty() || o->slice_spacing))
        throw Error(
            fmt::format("{}: --series, --units and --slice-spacing apply to DICOM only", o->input));
      DicomReadOptions options;
      options.series = o->series;
      options.units = o->units;
      options.slice_spacing_mm = o->slice_spacing;
      options.frame = o->frame.value_or(0);
      write_pyramid(o->input, o->output, o->frame.value_or(0), o->chunk,
                    dicom ? &options : nullptr);
      return 0;
    }
    if (!can_write_volume(o->output))
      throw Error(fmt::format("{}: unknown output format (supported: .nii.gz, .nii, .nrrd, .mha)",
                              o->output));
    std::vector<VolumeData> frames;
    std::vector<FrameLabel> labels;
    double repetition_s = 0.0;  // DICOM's RepetitionTime, the step dcm2niix writes
    if (is_dicom_source(o->input)) {
      DicomReadOptions options;
      options.series = o->series;
      options.units = o->units;
      options.slice_spacing_mm = o->slice_spacing;
      if (o->frame) {
        options.frame = *o->frame;
        DicomVolume dicom = read_dicom(o->input, options);
        print_notes(dicom.notes);
        frames.push_back(std::move(dicom.volume));
      } else {
        std::vector<DicomVolume> all = read_dicom_frames(o->input, options);
        print_notes(all.front().notes);
        labels = all.front().frame_labels;
        repetition_s = all.front().repetition_time_s.value_or(0.0);
        for (DicomVolume& d : all) frames.push_back(std::move(d.volume));
      }
    } else {
      if (!o->series.empty() || !o->units.empty() || o->slice_spacing)
        throw Error(
            fmt::format("{}: --series, --units and --slice-spacing apply to DICOM only", o->input));
      if (o->frame) {
        frames.push_back(read_volume(o->input, *o->frame));
      } else {
        const VolumeHeader header = read_volume_header(o->input);
        labels = header.frame_labels;
        for (int k = 0; k < header.frames; ++k) frames.push_back(read_volume(o->input, k));
      }
    }
    const VolumeData& first = frames.front();
    if (frames.size() == 1) {
      write_volume(first, o->output, !o->raw);
    } else {
      if (!is_nifti(o->output))
        throw Error(fmt::format(
            "{}: {} holds {} frames; only NIfTI (.nii.gz, .nii) holds them all (or give --frame "
            "K)",
            o->output, o->input, frames.size()));
      const VoxelType type = common_type(frames);
      for (VolumeData& f : frames) convert_to(f, type);
      const bool gzip = sidecar(o->output, "") + ".nii.gz" == o->output;
      write_nifti_frames(frames, o->output,
                         repetition_s > 0.0 ? repetition_s : frame_seconds(labels), gzip);
      if (!labels.empty()) {
        write_frame_labels(labels, o->output);
        // As dcm2niix: only a series with some diffusion weighting (b > 0 or a direction), not
        // the b = 0 labels of an fMRI, ASL or field map series.
        if (std::any_of(labels.begin(), labels.end(), [](const FrameLabel& l) {
              return l.b_value.value_or(0.0) > 0.0 ||
                     glm::length(l.b_vector.value_or(glm::dvec3(0.0))) > 0.0;
            }))
          write_diffusion(labels, first.index_to_world, o->output);
      }
    }
    if (!quiet())
      std::fprintf(stderr, "intermix: %s %dx%dx%d%s %s -> %s\n", o->input.c_str(), first.dims.x,
                   first.dims.y, first.dims.z,
                   frames.size() > 1 ? fmt::format("x{}", frames.size()).c_str() : "",
                   voxel_type_name(frames.front().type()), o->output.c_str());
    return 0;
  };
}

}  // namespace imx::cli
