// intermix phantom NAME -o OUT.nrrd|.mha|.nii.gz|.nii: writes a built-in phantom volume.
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "commands.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"

namespace imx::cli {

Command add_phantom(CLI::App& app) {
  struct Options {
    std::string name, output;
    int size = 128;
    bool raw = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("name", o->name, fmt::format("phantom: {}", fmt::join(phantom_names(), ", ")))
      ->required();
  app.add_option("-o,--output", o->output, "output file: .nrrd, .mha, .nii.gz or .nii")->required();
  app.add_option("--size", o->size, "voxels along the largest axis");
  app.add_flag("--raw", o->raw, "write uncompressed voxels");
  return [o]() {
    // The extension is checked before the phantom is built, which takes a while.
    if (!can_write_volume(o->output))
      throw Error(fmt::format("{}: unknown output format (supported: .nrrd, .mha, .nii.gz, .nii)",
                              o->output));
    VolumeData v = make_phantom(o->name, o->size);
    write_volume(v, o->output, !o->raw);
    if (!quiet())
      std::fprintf(stderr, "intermix: phantom %s %dx%dx%d %s -> %s\n", o->name.c_str(), v.dims.x,
                   v.dims.y, v.dims.z, voxel_type_name(v.type()), o->output.c_str());
    return 0;
  };
}

}  // namespace imx::cli
