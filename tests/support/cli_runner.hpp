// Runs the intermix and intermix-lab programs (and other commands) in tests and captures their
// exit code and output.
#pragma once
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace imx::test {

struct CliResult {
  int exit_code = -1;
  std::string output;  // what the command wrote to stdout (the programs': stdout and stderr)
};

// Whether `text` (a command's output) holds `part`.
inline bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Runs `command` in the shell; `output` is its stdout (add "2>&1" for its errors as well).
inline CliResult run_shell(const std::string& command) {
  CliResult r;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
  return r;
}

// `shell_prefix` runs before the program in the same shell (e.g. "ulimit -v 250000; ").
inline CliResult run_program(const char* program, const std::string& args,
                             const std::string& shell_prefix) {
  return run_shell(shell_prefix + std::string(program) + " --quiet " + args + " 2>&1");
}

inline CliResult run_cli(const std::string& args, const std::string& shell_prefix = "") {
  return run_program(IMX_CLI_PATH, args, shell_prefix);
}

inline CliResult run_lab(const std::string& args, const std::string& shell_prefix = "") {
  return run_program(IMX_LAB_PATH, args, shell_prefix);
}

}  // namespace imx::test
