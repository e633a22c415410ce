// The CLI's subcommands: each registers its options and returns the function that runs it.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

namespace imx::cli {

using Command = std::function<int()>;

Command add_render(CLI::App& app);
Command add_compare(CLI::App& app);
Command add_info(CLI::App& app);
Command add_phantom(CLI::App& app);
Command add_bench(CLI::App& app);
Command add_band(CLI::App& app);
Command add_zfight(CLI::App& app);
Command add_csg(CLI::App& app);
Command add_convert(CLI::App& app);
Command add_eval(CLI::App& app);
Command add_serve(CLI::App& app);

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

// Limits the CLI shares with the scene format.
inline constexpr int kMaxImageSide = 16384;
inline constexpr int kMaxSpp = 1024;

// Shared by commands: whether to show progress bars (stderr is a terminal and not --quiet).
bool show_progress();
bool quiet();
void set_quiet(bool quiet);
// Prints each of what loading chose for the user ("note: ..." on stderr), unless quiet.
void print_notes(const std::vector<std::string>& notes);

}  // namespace imx::cli
