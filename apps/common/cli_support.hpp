// What both programs (intermix and intermix-lab) share: the global options, running a
// subcommand with one error line and a status, progress and notes, and option validators.
#pragma once
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

namespace imx::cli {

// A subcommand registers its options and returns the function that runs it.
using Command = std::function<int()>;

struct Subcommand {
  const char* name;
  const char* help;
  Command (*add)(CLI::App& app);
};

// Parses argv (the global options --quiet, --verbose, --max-memory, --allow-external-data, then
// one subcommand) and runs the subcommand: an error is one line "PROGRAM: error: ..." on stderr
// and a non-zero status.
int run_program(const char* program, const char* description,
                std::span<const Subcommand> subcommands, int argc, char** argv);

// The program's name, for the lines commands print themselves ("intermix", "intermix-lab").
const char* program_name();

// A number in [lo, hi], with both bounds in the error message as short numbers (CLI11's own
// range checks print all 309 digits of DBL_MAX).
inline CLI::Validator in_range(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(text, v)) return fmt::format("{} is not a number", text);
        if (!(v >= lo && v <= hi)) return fmt::format("{} is not in [{:g}, {:g}]", text, lo, hi);
        return {};
      },
      fmt::format("in [{:g}, {:g}]", lo, hi));
}

// "8G", "512M", "1.5GiB", "300k" or bytes.
CLI::Validator byte_size();

// Limits the CLI shares with the scene format.
inline constexpr int kMaxImageSide = 16384;
inline constexpr int kMaxSpp = 1024;

// The scene options commands share, with one wording and one range each.
struct SceneOptions {
  int width = 0, height = 0, spp = 0, threads = 0;  // 0: the scene's (threads: all cores)
  std::vector<std::string> overrides;               // --set key.path=value, in order
  // `overrides` with --width and --height (when given) as image.width and image.height.
  std::vector<std::string> with_size() const;
};
enum SceneOption : unsigned { kSizeOption = 1, kSppOption = 2, kThreadsOption = 4, kSetOption = 8 };
inline constexpr unsigned kAllSceneOptions = kSizeOption | kSppOption | kThreadsOption | kSetOption;
// Adds --width and --height, --spp, --threads and --set as `which` asks; `scope` ends their
// help ("for --intervals"), and --set's says whether it applies to every scene.
void add_scene_options(CLI::App& app, SceneOptions& o, unsigned which = kAllSceneOptions,
                       const std::string& scope = "");

// Whether to show progress bars (stderr is a terminal and not --quiet).
bool show_progress();
bool quiet();
// Prints each of what loading chose for the user ("note: ..." on stderr), unless quiet.
void print_notes(const std::vector<std::string>& notes);

}  // namespace imx::cli
