// intermix convert IN -o OUT: any volume intermix reads (a DICOM series too), written as
// NIfTI, NRRD or MetaImage, so its geometry can be checked in another tool.
#include <cstdio>
#include <optional>

#include <fmt/format.h>

#include "commands.hpp"
#include "intermix/dicom.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"

namespace imx::cli {

Command add_convert(CLI::App& app) {
  struct Options {
    std::string input, output, series, units;
    std::optional<double> slice_spacing;
    bool raw = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("input", o->input,
                 "volume file (.nrrd, .nhdr, .nii, .nii.gz, .mha, .mhd), DICOM file, DICOMDIR "
                 "or folder")
      ->required();
  app.add_option("-o,--output", o->output, "output file: .nii.gz, .nii, .nrrd or .mha")->required();
  app.add_option("--series", o->series, "DICOM: the series number or SeriesInstanceUID");
  app.add_option("--units", o->units, "DICOM PET: 'suv' for standardized uptake values")
      ->check(CLI::IsMember({"suv"}));
  app.add_option("--slice-spacing", o->slice_spacing,
                 "DICOM with uneven slice gaps: resample at this spacing in mm (default: the "
                 "smallest gap)")
      ->check(in_range(1e-3, 1e3));
  app.add_flag("--raw", o->raw, "write uncompressed voxels (NRRD, MetaImage)");
  return [o]() {
    if (!can_write_volume(o->output))
      throw Error(fmt::format("{}: unknown output format (supported: .nii.gz, .nii, .nrrd, .mha)",
                              o->output));
    VolumeData volume;
    if (is_dicom_source(o->input)) {
      DicomReadOptions options;
      options.series = o->series;
      options.units = o->units;
      options.slice_spacing_mm = o->slice_spacing;
      DicomVolume dicom = read_dicom(o->input, options);
      print_notes(dicom.notes);
      volume = std::move(dicom.volume);
    } else {
      if (!o->series.empty() || !o->units.empty() || o->slice_spacing)
        throw Error(
            fmt::format("{}: --series, --units and --slice-spacing apply to DICOM only", o->input));
      volume = read_volume(o->input);
    }
    write_volume(volume, o->output, !o->raw);
    if (!quiet())
      std::fprintf(stderr, "intermix: %s %dx%dx%d %s -> %s\n", o->input.c_str(), volume.dims.x,
                   volume.dims.y, volume.dims.z, voxel_type_name(volume.type()), o->output.c_str());
    return 0;
  };
}

}  // namespace imx::cli
