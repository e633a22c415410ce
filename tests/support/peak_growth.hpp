// PeakGrowth: how much a piece of code raised the process's peak resident memory.
#pragma once
#include <cstdint>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace imx::test {

// What AddressSanitizer adds to a peak (its quarantine keeps freed blocks resident for a while,
// its redzones pad each one): the memory tests' bounds allow this much more in a sanitizer build.
#ifdef IMX_SANITIZED
inline constexpr int64_t kSanitizerSlackMiB = 32;
#else
inline constexpr int64_t kSanitizerSlackMiB = 0;
#endif

// A field of /proc/self/status in KiB ("VmRSS", "VmHWM").
inline int64_t status_kib(const std::string& field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind(field + ":", 0) == 0) return std::stoll(line.substr(field.size() + 1));
  ADD_FAILURE() << "no " << field << " in /proc/self/status";
  return 0;
}

// The growth of the peak resident memory from its construction: the high-water mark is reset to
// the resident memory then (Linux 4.0+), so memory touched and freed before cannot hide what
// follows; where the kernel refuses, it counts from the old mark, which can hide some.
class PeakGrowth {
 public:
  PeakGrowth() {
    std::ofstream reset("/proc/self/clear_refs");
    reset << "5";
    reset.flush();
    start_kib_ = status_kib(reset ? "VmRSS" : "VmHWM");
  }
  int64_t kib() const { return status_kib("VmHWM") - start_kib_; }
  int64_t mib() const { return kib() / 1024; }

 private:
  int64_t start_kib_ = 0;
};

}  // namespace imx::test
