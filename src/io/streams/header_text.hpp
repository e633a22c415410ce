// Helpers for the small text headers of volume formats (NRRD, MetaImage).
#pragma once
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace imx::detail {

// Header limits: anything beyond them is binary data or a corrupt file, not a header.
inline constexpr size_t kMaxHeaderLineBytes = size_t{1} << 16;
inline constexpr size_t kMaxHeaderBytes = size_t{1} << 20;

inline std::string_view trim(std::string_view s) {
  size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return {};
  size_t e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

// A value for an error message: long text is cut short and binary bytes become '?'.
inline std::string shown(std::string_view s) {
  constexpr size_t kMax = 80;
  std::string out(s.substr(0, kMax));
  for (char& c : out)
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  return s.size() <= kMax ? out : out + "...";
}

inline std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

// The blank-separated words of a header value.
inline std::vector<std::string_view> split_words(std::string_view s) {
  std::vector<std::string_view> words;
  size_t i = 0;
  while (i < s.size()) {
    size_t b = s.find_first_not_of(" \t\r", i);
    if (b == std::string_view::npos) break;
    size_t e = s.find_first_of(" \t\r", b);
    if (e == std::string_view::npos) e = s.size();
    words.push_back(s.substr(b, e - b));
    i = e;
  }
  return words;
}

// A number that is the whole of `s` (spaces around it and a leading '+' allowed), else nullopt.
template <class T>
std::optional<T> parse_header_number(std::string_view s) {
  s = trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  T v{};
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

}  // namespace imx::detail
