#include "io/volume/afni_attributes.hpp"

#include <optional>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/header_text.hpp"

namespace imx::detail {

namespace {

constexpr std::string_view kBlank = " \t\r\n\f\v";

std::string_view strip(std::string_view s) {
  const size_t b = s.find_first_not_of(kBlank);
  if (b == std::string_view::npos) return {};
  return s.substr(b, s.find_last_not_of(kBlank) - b + 1);
}

bool is_name(std::string_view s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  return true;
}

// One attribute: its first three lines are "type = ...", "name = ..." and "count = ..." (in
// any order, as nibabel finds them by pattern); the lines after them are the value, joined by
// spaces as nibabel joins them.
std::pair<std::string, AfniAttribute> parse_block(std::string_view block, size_t number,
                                                  const std::string& what) {
  std::vector<std::string_view> lines;
  for (size_t at = 0; at <= block.size();) {
    size_t end = block.find('\n', at);
    if (end == std::string_view::npos) end = block.size();
    std::string_view line = block.substr(at, end - at);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    at = end + 1;
  }
  auto bad = [&](const std::string& why) {
    return Error(fmt::format("{}: attribute {} of the HEAD file (starting '{}') {}", what, number,
                             shown(lines.front()), why));
  };
  if (lines.size() < 3) throw bad("lacks its type, name and count lines");
  std::optional<std::string_view> type, name, count;
  for (size_t k = 0; k < 3; ++k) {
    const size_t eq = lines[k].find('=');
    const std::string_view key = eq == std::string_view::npos ? "" : strip(lines[k].substr(0, eq));
    std::optional<std::string_view>* slot = key == "type"    ? &type
                                            : key == "name"  ? &name
                                            : key == "count" ? &count
                                                             : nullptr;
    if (!slot || *slot)
      throw bad(fmt::format("has line '{}' where 'type = ', 'name = ' and 'count = ' lines belong",
                            shown(lines[k])));
    *slot = strip(lines[k].substr(eq + 1));
  }
  if (!is_name(*name)) throw bad(fmt::format("has name '{}', not a word", shown(*name)));
  AfniAttribute a;
  if (*type == "string-attribute")
    a.kind = AfniAttribute::Kind::string;
  else if (*type == "integer-attribute")
    a.kind = AfniAttribute::Kind::integer;
  else if (*type == "float-attribute")
    a.kind = AfniAttribute::Kind::floating;
  else
    throw Error(
        fmt::format("{}: attribute {} has type '{}' (string-attribute, integer-attribute "
                    "or float-attribute expected)",
                    what, *name, shown(*type)));
  const std::optional<long long> n = parse_header_number<long long>(*count);
  std::string value;
  for (size_t k = 3; k < lines.size(); ++k) {
    if (k > 3) value += ' ';
    value += lines[k];
  }
  // Every number takes at least one character, and a string's count is its length: a count
  // beyond the value's length is a lie, caught before anything is sized by it.
  if (!n || *n < 0 || static_cast<unsigned long long>(*n) > value.size() + 1)
    throw Error(
        fmt::format("{}: attribute {} has count '{}', not a number of values its {} "
                    "characters can hold",
                    what, *name, shown(*count), value.size()));
  if (a.kind == AfniAttribute::Kind::string) {
    const std::string_view v = strip(value);
    if (*n > 0 && (v.empty() || v.front() != '\''))
      throw Error(
          fmt::format("{}: string attribute {} does not start with a quote (')", what, *name));
    std::string_view text = v.empty() ? v : v.substr(1);
    if (text.size() != static_cast<size_t>(*n))
      throw Error(fmt::format("{}: string attribute {} has count {} but holds {} characters", what,
                              *name, *n, text.size()));
    while (!text.empty() && text.back() == '~') text.remove_suffix(1);  // AFNI's NUL
    a.text = std::string(text);
  } else {
    const std::vector<std::string_view> words = split_words(value);
    if (words.size() != static_cast<size_t>(*n))
      throw Error(fmt::format("{}: attribute {} has count {} but holds {} values", what, *name, *n,
                              words.size()));
    a.numbers.reserve(words.size());
    for (std::string_view w : words) {
      std::optional<double> v;
      if (a.kind == AfniAttribute::Kind::integer) {
        if (const std::optional<long long> i = parse_header_number<long long>(w))
          v = static_cast<double>(*i);
      } else {
        v = parse_header_number<double>(w);
      }
      if (!v)
        throw Error(
            fmt::format("{}: attribute {} holds '{}', not {}", what, *name, shown(w),
                        a.kind == AfniAttribute::Kind::integer ? "an integer" : "a number"));
      a.numbers.push_back(*v);
    }
  }
  return {std::string(*name), std::move(a)};
}

}  // namespace

AfniAttributes parse_afni_attributes(std::string_view head, const std::string& what) {
  AfniAttributes attributes;
  size_t number = 0;
  for (size_t at = 0; at <= head.size();) {
    size_t end = head.find("\n\n", at);
    if (end == std::string_view::npos) end = head.size();
    const std::string_view block = strip(head.substr(at, end - at));
    at = end + 2;
    if (block.empty()) continue;
    auto [name, attribute] = parse_block(block, ++number, what);
    attributes.insert_or_assign(std::move(name), std::move(attribute));
  }
  if (attributes.empty())
    throw Error(fmt::format("{}: no AFNI attributes ('type = ...-attribute' blocks) found", what));
  return attributes;
}

}  // namespace imx::detail
