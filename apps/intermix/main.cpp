// intermix: the command-line program (render, compare, info, phantom, bench).
#include <cstdio>
#include <exception>
#include <map>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "core/progress_bar.hpp"
#include "intermix/error.hpp"

namespace imx::cli {
namespace {
bool quiet_flag = false;
}
bool show_progress() {
  return !quiet_flag && stderr_is_terminal();
}
bool quiet() {
  return quiet_flag;
}
void set_quiet(bool quiet) {
  quiet_flag = quiet;
}
}  // namespace imx::cli

int main(int argc, char** argv) {
  CLI::App app{"intermix: renders volumes, meshes and planes into one correct image"};
  app.require_subcommand(1);
  bool quiet = false;
  app.add_flag("-q,--quiet", quiet, "no progress bars or timing lines");
  std::map<CLI::App*, imx::cli::Command> commands;
  auto add = [&](const char* name, const char* help, auto adder) {
    CLI::App* sub = app.add_subcommand(name, help);
    commands[sub] = adder(*sub);
  };
  add("render", "render a scene file to PNG", imx::cli::add_render);
  add("compare", "PSNR, SSIM and error fractions between two PNG images", imx::cli::add_compare);
  add("info", "describe a volume or mesh file, or a built-in phantom", imx::cli::add_info);
  add("phantom", "write a built-in phantom volume as NRRD", imx::cli::add_phantom);
  add("bench", "time methods on a scene: median/min/max ms per frame", imx::cli::add_bench);
  add("band", "PSNR in the band around two objects' intersection curves", imx::cli::add_band);
  add("zfight", "z-fighting metric of methods where coplanar surfaces coincide",
      imx::cli::add_zfight);
  add("csg", "a CSG scene's primitives, products, clipping states and intervals per ray",
      imx::cli::add_csg);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  imx::cli::set_quiet(quiet);
  try {
    for (CLI::App* sub : app.get_subcommands()) return commands.at(sub)();
  } catch (const imx::Error& e) {
    std::fprintf(stderr, "intermix: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "intermix: unexpected error: %s\n", e.what());
    return 2;
  }
  return 0;
}
