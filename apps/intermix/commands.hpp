// The CLI's subcommands: each registers its options and returns the function that runs it.
#pragma once
#include <functional>

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

// Shared by commands: whether to show progress bars (stderr is a terminal and not --quiet).
bool show_progress();
bool quiet();
void set_quiet(bool quiet);

}  // namespace imx::cli
