// intermix's subcommands, for users: render, serve, info, convert, phantom, compare, figure.
#pragma once
#include "cli_support.hpp"

namespace imx::cli {

Command add_render(CLI::App& app);
Command add_serve(CLI::App& app);
Command add_info(CLI::App& app);
Command add_convert(CLI::App& app);
Command add_phantom(CLI::App& app);
Command add_compare(CLI::App& app);
Command add_figure(CLI::App& app);

}  // namespace imx::cli
