#include "core/library_output.hpp"

#include <deque>
#include <mutex>

#include <fmt/format.h>

namespace imx::detail {

namespace {

constexpr size_t kMaxLines = 200;
constexpr size_t kMaxLineLength = 500;

std::mutex& output_mutex() {
  static std::mutex m;
  return m;
}

std::deque<std::string>& kept_lines() {
  static std::deque<std::string> lines;
  return lines;
}

}  // namespace

void keep_library_output(std::string_view from, std::string_view what, std::string_view text) {
  std::lock_guard lock(output_mutex());
  std::deque<std::string>& lines = kept_lines();
  while (!text.empty()) {
    const size_t cut = text.find('\n');
    std::string_view line = text.substr(0, cut);
    text = cut == std::string_view::npos ? std::string_view() : text.substr(cut + 1);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.remove_suffix(1);
    if (line.empty()) continue;
    lines.push_back(fmt::format("{} ({}): {}", from, what, line.substr(0, kMaxLineLength)));
    if (lines.size() > kMaxLines) lines.pop_front();
  }
}

std::vector<std::string> take_library_output() {
  std::lock_guard lock(output_mutex());
  std::vector<std::string> out(kept_lines().begin(), kept_lines().end());
  kept_lines().clear();
  return out;
}

}  // namespace imx::detail
