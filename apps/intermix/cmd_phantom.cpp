// intermix phantom NAME -o OUT.nrrd|OUT.mha: writes a built-in phantom volume.
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "commands.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"

namespace imx::cli {

namespace {

// The writer follows the extension, checked before the phantom is built (which takes a while).
enum class VolumeFormat { nrrd, metaimage };

VolumeFormat format_for(const std::string& output) {
  std::string ext = std::filesystem::path(output).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".nrrd" || ext == ".nhdr") return VolumeFormat::nrrd;
  if (ext == ".mha") return VolumeFormat::metaimage;
  throw Error(fmt::format("{}: unknown output format '{}' (supported: .nrrd, .mha)", output, ext));
}

}  // namespace

Command add_phantom(CLI::App& app) {
  struct Options {
    std::string name, output;
    int size = 128;
    bool raw = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("name", o->name, fmt::format("phantom: {}", fmt::join(phantom_names(), ", ")))
      ->required();
  app.add_option("-o,--output", o->output, "output file: .nrrd (NRRD) or .mha (MetaImage)")
      ->required();
  app.add_option("--size", o->size, "voxels along the largest axis");
  app.add_flag("--raw", o->raw, "write uncompressed voxels");
  return [o]() {
    VolumeFormat format = format_for(o->output);
    VolumeData v = make_phantom(o->name, o->size);
    if (format == VolumeFormat::nrrd)
      write_nrrd(v, o->output, !o->raw);
    else
      write_metaimage(v, o->output, !o->raw);
    if (!quiet())
      std::fprintf(stderr, "intermix: phantom %s %dx%dx%d %s -> %s\n", o->name.c_str(), v.dims.x,
                   v.dims.y, v.dims.z, voxel_type_name(v.type()), o->output.c_str());
    return 0;
  };
}

}  // namespace imx::cli
