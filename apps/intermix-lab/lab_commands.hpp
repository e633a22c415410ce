// intermix-lab's subcommands, for measuring methods: eval, bench (with --vtk), zfight, band, csg.
#pragma once
#include "cli_support.hpp"

namespace imx::cli {

Command add_eval(CLI::App& app);
Command add_bench(CLI::App& app);
Command add_zfight(CLI::App& app);
Command add_band(CLI::App& app);
Command add_csg(CLI::App& app);

}  // namespace imx::cli
