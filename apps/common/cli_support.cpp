#include "cli_support.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <new>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/library_output.hpp"
#include "core/parallel.hpp"
#include "core/progress_bar.hpp"
#include "intermix/error.hpp"
#include "intermix/limits.hpp"

namespace imx::cli {
namespace {

bool quiet_flag = false;
const char* program = "intermix";

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

// The positional arguments a command was given (its input files, mostly): what a message with
// no file of its own names.
std::string inputs_of(const CLI::App& command) {
  std::vector<std::string> words;
  for (const CLI::Option* o : command.get_options())
    if (o->get_positional())
      for (const std::string& r : o->results()) words.push_back(r);
  return words.empty() ? command.get_name() : fmt::format("{}", fmt::join(words, " "));
}

// Runs a command; an error is one line on stderr and a non-zero status. Running out of memory
// where no reader caught it names the command's inputs.
int run_command(const Command& command, const std::string& inputs) {
  try {
    return command();
  } catch (const Error& e) {
    std::fprintf(stderr, "%s: error: %s\n", program, e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "%s: error: %s\n", program, out_of_memory_message(inputs).c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: unexpected error: %s\n", program, e.what());
    return 2;
  }
}

}  // namespace

const char* program_name() {
  return program;
}

bool show_progress() {
  return !quiet_flag && stderr_is_terminal();
}

bool quiet() {
  return quiet_flag;
}

void print_notes(const std::vector<std::string>& notes) {
  if (quiet_flag) return;
  for (const std::string& note : notes)
    std::fprintf(stderr, "%s: note: %s\n", program, note.c_str());
}

CLI::Validator byte_size() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        return parse_byte_size(text) != 0
                   ? std::string()
                   : text + " is not a size (give bytes, or a number with K, M, G or T)";
      },
      "SIZE");
}

int run_program(const char* name, const char* description, std::span<const Subcommand> subcommands,
                int argc, char** argv) {
  program = name;
  CLI::App app{description};
  app.require_subcommand(1);
  bool verbose = false;
  app.add_flag("-q,--quiet", quiet_flag, "no progress bars or timing lines");
  app.add_flag("-v,--verbose", verbose,
               "also print what libraries said (decoders' warnings), after intermix's own lines");
  std::string max_memory;
  bool allow_external_data = false;
  app.add_option("--max-memory", max_memory,
                 fmt::format("memory one input or frame may ask for, e.g. 8G (default: half of "
                             "physical memory, {})",
                             format_bytes(default_memory_budget())))
      ->check(byte_size());
  app.add_flag("--allow-external-data", allow_external_data,
               "let volume headers name data files outside their own folder");
  std::map<CLI::App*, Command> commands;
  for (const Subcommand& s : subcommands) {
    CLI::App* sub = app.add_subcommand(s.name, s.help);
    commands[sub] = s.add(*sub);
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  InputLimits limits;
  if (!max_memory.empty()) limits.max_memory = parse_byte_size(max_memory);
  limits.allow_external_data = allow_external_data;
  set_input_limits(limits);
  CLI::App* command = app.get_subcommands().front();
  const int status = run_command(commands.at(command), inputs_of(*command));
  // Libraries' own words come last, and only when asked for.
  if (verbose)
    for (const std::string& line : detail::take_library_output())
      std::fprintf(stderr, "%s: library: %s\n", program, line.c_str());
  return status;
}

std::vector<std::string> SceneOptions::with_size() const {
  std::vector<std::string> out = overrides;
  if (width > 0) out.push_back(fmt::format("image.width={}", width));
  if (height > 0) out.push_back(fmt::format("image.height={}", height));
  return out;
}

void add_scene_options(CLI::App& app, SceneOptions& o, unsigned which, const std::string& scope) {
  const std::string tail = scope.empty() ? "" : " " + scope;
  if (which & kSizeOption) {
    app.add_option("--width", o.width, "image width in pixels (overrides the scene)" + tail)
        ->check(in_range(1, kMaxImageSide));
    app.add_option("--height", o.height, "image height in pixels (overrides the scene)" + tail)
        ->check(in_range(1, kMaxImageSide));
  }
  if (which & kSppOption)
    app.add_option("--spp", o.spp,
                   "samples per pixel, a perfect square (1, 4, 16, 64, ...; default: the "
                   "scene's)" +
                       tail)
        ->check(in_range(1, kMaxSpp));
  if (which & kThreadsOption)
    app.add_option("--threads", o.threads, "worker threads (default: all cores)" + tail)
        ->check(in_range(0, kMaxThreads));
  if (which & kSetOption)
    app.add_option("--set", o.overrides,
                   "override a scene value: key.path=value (repeatable)" + tail);
}

}  // namespace imx::cli
