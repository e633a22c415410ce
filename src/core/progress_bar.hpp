// ProgressBar: a one-line progress indicator on stderr for long work (only on a terminal).
#pragma once
#include <chrono>
#include <string>

namespace imx {

class ProgressBar {
 public:
  // `enabled` false makes every call a no-op (non-terminals, --quiet, tests).
  ProgressBar(std::string label, bool enabled);
  ~ProgressBar();
  void update(double fraction);
  void finish();

 private:
  std::string label_;
  bool enabled_;
  bool finished_ = false;
  int last_percent_ = -1;
  std::chrono::steady_clock::time_point start_;
};

// True when stderr is a terminal.
bool stderr_is_terminal();

}  // namespace imx
