// Linear-time checks of parsers (issue 48, item 3): an input at the size limit against 16 inputs
// a sixteenth of its size, so that both sides read the same bytes and a loaded machine slows them
// alike. The bound, time(n) / time(n/16) <= 32, is a growth of 2 over linear here; linear
// parsers measure 1-2 (the whole input outgrows the caches), a quadratic one 16.
#pragma once
#include <algorithm>
#include <chrono>
#include <functional>
#include <string>

namespace imx::test {

// time(parse(full)) / (16 time(parse(part))), the best of `runs` each: a loaded machine adds
// time, never takes it away.
inline double growth_over_linear(const std::function<void(const std::string&)>& parse,
                                 const std::string& full, const std::string& part, int runs = 5) {
  auto seconds = [&](const std::string& input, int times) {
    double best = 1e9;
    for (int run = 0; run < runs; ++run) {
      const auto t0 = std::chrono::steady_clock::now();
      for (int k = 0; k < times; ++k) parse(input);
      best = std::min(best,
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return best;
  };
  return seconds(full, 1) / seconds(part, 16);
}

// The bound the tests hold: the 32 for time(n) / time(n/16), with the room a shared
// machine needs (the seg.nrrd test's measure, 1.6-2.1, held under load).
inline constexpr double kMaxGrowthOverLinear = 4.0;

// `unit` repeated after `head` until the text reaches `bytes` (never past it).
inline std::string repeated_to(const std::string& head, const std::string& unit, size_t bytes) {
  std::string s = head;
  while (s.size() + unit.size() <= bytes) s += unit;
  return s;
}

}  // namespace imx::test
