// intermix: the program for users (render, serve, info, convert, phantom, compare). Measurement
// (eval, bench, zfight, band, csg) is intermix-lab's.
#include "commands.hpp"

int main(int argc, char** argv) {
  using namespace imx::cli;
  static constexpr Subcommand kSubcommands[] = {
      {"render", "render a scene file to PNG", add_render},
      {"serve", "the interactive viewer: serves the scene to a browser", add_serve},
      {"info", "describe a volume or mesh file, or a built-in phantom", add_info},
      {"convert", "write a volume (a DICOM series, NRRD, ...) as NIfTI, NRRD or MetaImage",
       add_convert},
      {"phantom", "write a built-in phantom volume as NRRD, MetaImage or NIfTI", add_phantom},
      {"compare", "PSNR, SSIM and error fractions between two PNG images", add_compare},
  };
  return run_program("intermix",
                     "intermix: renders volumes, meshes and planes into one correct image",
                     kSubcommands, argc, argv);
}
