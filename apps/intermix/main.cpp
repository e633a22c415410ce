// intermix: the program for users (render, serve, info, convert, phantom, compare, figure). Measurement
// (eval, bench, zfight, band, csg) is intermix-lab's.
#include <cstdio>
#include <cstdlib>

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
      {"figure", "a figure for a paper: ortho, mosaic or glass-brain panels of a map over anatomy",
       add_figure},
  };
  const int status =
      run_program("intermix", "intermix: renders volumes, meshes and planes into one correct image",
                  kSubcommands, argc, argv);
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define IMX_LEAK_CHECK_AT_EXIT 1
#endif
#endif
#if !defined(IMX_LEAK_CHECK_AT_EXIT) && !defined(__SANITIZE_ADDRESS__)
  // Every output is written and closed by now: the libraries' destructors (GDCM's dictionaries,
  // thousands of frees) would only cost time. Sanitizer builds exit normally, for the leak check.
  std::fflush(nullptr);
  std::_Exit(status);
#endif
  return status;
}
