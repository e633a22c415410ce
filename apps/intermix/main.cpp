// intermix: the command-line program (render, compare, info, phantom, bench, eval, ...).
#include <cctype>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <new>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "core/library_output.hpp"
#include "core/progress_bar.hpp"
#include "intermix/error.hpp"
#include "intermix/limits.hpp"

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
void print_notes(const std::vector<std::string>& notes) {
  if (quiet_flag) return;
  for (const std::string& note : notes) std::fprintf(stderr, "intermix: note: %s\n", note.c_str());
}
void set_quiet(bool quiet) {
  quiet_flag = quiet;
}

namespace {

// "8G", "512M", "1.5GiB", "300k", or bytes: a size in bytes, 0 when the text is none of those.
uint64_t parse_byte_size(const std::string& text) {
  size_t used = 0;
  double number = 0.0;
  try {
    number = std::stod(text, &used);
  } catch (const std::exception&) {
    return 0;
  }
  std::string unit = text.substr(used);
  for (char& c : unit) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (unit.size() > 1 && unit.back() == 'b') unit.pop_back();  // "GB", "GiB"
  if (unit.size() > 1 && unit.back() == 'i') unit.pop_back();
  double scale = unit.empty()  ? 1.0
                 : unit == "k" ? 1024.0
                 : unit == "m" ? 1024.0 * 1024
                 : unit == "g" ? 1024.0 * 1024 * 1024
                 : unit == "t" ? 1024.0 * 1024 * 1024 * 1024
                               : 0.0;
  double bytes = number * scale;
  return std::isfinite(bytes) && bytes >= 1.0 && bytes < 1.8e19 ? static_cast<uint64_t>(bytes) : 0;
}

}  // namespace

CLI::Validator byte_size() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        return parse_byte_size(text) != 0
                   ? std::string()
                   : text + " is not a size (give bytes, or a number with K, M, G or T)";
      },
      "SIZE");
}
// Runs a command; an error is one line on stderr and a non-zero status.
int run_command(const Command& command) {
  try {
    return command();
  } catch (const imx::Error& e) {
    std::fprintf(stderr, "intermix: error: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "intermix: error: %s\n", imx::out_of_memory_message("intermix").c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "intermix: unexpected error: %s\n", e.what());
    return 2;
  }
}

}  // namespace imx::cli

int main(int argc, char** argv) {
  CLI::App app{"intermix: renders volumes, meshes and planes into one correct image"};
  app.require_subcommand(1);
  bool quiet = false;
  app.add_flag("-q,--quiet", quiet, "no progress bars or timing lines");
  bool verbose = false;
  app.add_flag("-v,--verbose", verbose,
               "also print what libraries said (decoders' warnings), after intermix's own lines");
  std::string max_memory;
  bool allow_external_data = false;
  app.add_option("--max-memory", max_memory,
                 fmt::format("memory one input or frame may ask for, e.g. 8G (default: half of "
                             "physical memory, {})",
                             imx::format_bytes(imx::default_memory_budget())))
      ->check(imx::cli::byte_size());
  app.add_flag("--allow-external-data", allow_external_data,
               "let volume headers name data files outside their own folder");
  std::map<CLI::App*, imx::cli::Command> commands;
  auto add = [&](const char* name, const char* help, auto adder) {
    CLI::App* sub = app.add_subcommand(name, help);
    commands[sub] = adder(*sub);
  };
  add("render", "render a scene file to PNG", imx::cli::add_render);
  add("compare", "PSNR, SSIM and error fractions between two PNG images", imx::cli::add_compare);
  add("info", "describe a volume or mesh file, or a built-in phantom", imx::cli::add_info);
  add("phantom", "write a built-in phantom volume as NRRD, MetaImage or NIfTI",
      imx::cli::add_phantom);
  add("convert", "write a volume (a DICOM series, NRRD, ...) as NIfTI, NRRD or MetaImage",
      imx::cli::add_convert);
  add("bench", "time methods on a scene: median/min/max ms per frame", imx::cli::add_bench);
  add("band", "PSNR in the band around two objects' intersection curves", imx::cli::add_band);
  add("zfight", "z-fighting metric of methods where coplanar surfaces coincide",
      imx::cli::add_zfight);
  add("csg", "a CSG scene's primitives, products, clipping states and intervals per ray",
      imx::cli::add_csg);
  add("eval", "every method on every scene against the reference: HTML report, JSON, tables",
      imx::cli::add_eval);
  add("serve", "the interactive viewer: serves the scene to a browser", imx::cli::add_serve);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  imx::cli::set_quiet(quiet);
  imx::InputLimits limits;
  if (!max_memory.empty()) limits.max_memory = imx::cli::parse_byte_size(max_memory);
  limits.allow_external_data = allow_external_data;
  imx::set_input_limits(limits);
  const int status = imx::cli::run_command(commands.at(app.get_subcommands().front()));
  // Libraries' own words come last, and only when asked for.
  if (verbose)
    for (const std::string& line : imx::detail::take_library_output())
      std::fprintf(stderr, "intermix: library: %s\n", line.c_str());
  return status;
}
