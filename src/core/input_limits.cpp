#include <atomic>

#include <unistd.h>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"

namespace imx {
namespace {

// Relaxed atomics: set once before work starts, read by any thread.
std::atomic<uint64_t> max_memory{0};
std::atomic<bool> allow_external_data{false};

}  // namespace

uint64_t default_memory_budget() {
  long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return uint64_t{4} << 30;  // unknown: 4 GiB
  return static_cast<uint64_t>(pages) * static_cast<uint64_t>(page_size) / 2;
}

void set_input_limits(const InputLimits& limits) {
  max_memory.store(limits.max_memory, std::memory_order_relaxed);
  allow_external_data.store(limits.allow_external_data, std::memory_order_relaxed);
}

InputLimits input_limits() {
  uint64_t budget = max_memory.load(std::memory_order_relaxed);
  return {budget != 0 ? budget : default_memory_budget(),
          allow_external_data.load(std::memory_order_relaxed)};
}

std::string format_bytes(uint64_t bytes) {
  const double b = static_cast<double>(bytes);
  if (b >= 1024.0 * 1024 * 1024) return fmt::format("{:.1f} GiB", b / (1024.0 * 1024 * 1024));
  if (b >= 1024.0 * 1024) return fmt::format("{:.1f} MiB", b / (1024.0 * 1024));
  if (b >= 1024.0) return fmt::format("{:.1f} KiB", b / 1024.0);
  return fmt::format("{} bytes", bytes);
}

void check_memory(uint64_t bytes, const std::string& what) {
  const uint64_t budget = input_limits().max_memory;
  if (bytes > budget)
    throw OutOfMemory(
        fmt::format("{} needs {}, more than the memory budget of {} (raise it with "
                    "--max-memory)",
                    what, format_bytes(bytes), format_bytes(budget)));
}

std::string out_of_memory_message(const std::string& what) {
  return fmt::format(
      "{}: out of memory: the machine could not give what this input asked for, although it is "
      "within the memory budget of {} (lower the budget with --max-memory, or free memory)",
      what, format_bytes(input_limits().max_memory));
}

}  // namespace imx
