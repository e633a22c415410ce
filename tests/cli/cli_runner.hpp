// Runs the intermix and intermix-lab programs in tests and captures their exit code and output.
#pragma once
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace imx::test {

struct CliResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// `shell_prefix` runs before the program in the same shell (e.g. "ulimit -v 250000; ").
inline CliResult run_program(const char* program, const std::string& args,
                             const std::string& shell_prefix) {
  std::string cmd = shell_prefix + std::string(program) + " --quiet " + args + " 2>&1";
  CliResult r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
  return r;
}

inline CliResult run_cli(const std::string& args, const std::string& shell_prefix = "") {
  return run_program(IMX_CLI_PATH, args, shell_prefix);
}

inline CliResult run_lab(const std::string& args, const std::string& shell_prefix = "") {
  return run_program(IMX_LAB_PATH, args, shell_prefix);
}

// A fresh empty folder for one test.
inline std::filesystem::path temp_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("intermix-cli-" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline void write_text(const std::filesystem::path& file, const std::string& text) {
  std::ofstream(file) << text;
}

inline std::string read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace imx::test
