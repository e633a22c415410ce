// Process-wide limits on what inputs may make intermix do: how much memory it allocates for
// them and which files their headers may name. Set once at start-up (the CLI's --max-memory and
// --allow-external-data); every reader and render checks against them.
#pragma once
#include <cstdint>
#include <string>

namespace imx {

struct InputLimits {
  uint64_t max_memory = 0;           // bytes one input or frame may ask for; 0: the default
  bool allow_external_data = false;  // header-named data files outside the header's folder
};

// Half of the machine's physical memory: the default max_memory.
uint64_t default_memory_budget();

void set_input_limits(const InputLimits& limits);
// The limits in force, with max_memory resolved (never 0).
InputLimits input_limits();

// Throws imx::Error "`what` needs N GiB, more than the memory budget of M GiB (--max-memory)"
// when `bytes` exceed the budget. Called before any allocation whose size an input decides.
void check_memory(uint64_t bytes, const std::string& what);

// "WHAT: out of memory: ... within the memory budget of M GiB": the message for a std::bad_alloc
// while reading or rendering `what` (a file, or a scene's JSON path).
std::string out_of_memory_message(const std::string& what);

// "12.5 GiB", "300 MiB", "512 bytes": for messages.
std::string format_bytes(uint64_t bytes);

}  // namespace imx
