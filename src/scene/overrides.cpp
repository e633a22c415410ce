#include "scene/overrides.hpp"

#include <algorithm>
#include <cctype>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "core/edit_distance.hpp"
#include "scene/strict_json.hpp"

namespace imx::scene_json {
namespace {

bool is_index(const std::string& token) {
  return !token.empty() &&
         std::all_of(token.begin(), token.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// Splits "a.b[0].c" into a, b, 0, c; returns false on an empty part or unbalanced brackets.
bool split_path(const std::string& path, std::vector<std::string>& tokens) {
  std::string cur;
  size_t i = 0;
  bool after_bracket = false;  // "]" may be followed only by "." or "["
  while (i < path.size()) {
    char c = path[i];
    if (c == '.') {
      if (cur.empty() && !after_bracket) return false;
      if (!cur.empty()) tokens.push_back(cur);
      cur.clear();
      after_bracket = false;
      ++i;
      if (i == path.size()) return false;
    } else if (c == '[') {
      if (!cur.empty()) tokens.push_back(cur);
      cur.clear();
      size_t close = path.find(']', i);
      if (close == std::string::npos || close == i + 1) return false;
      tokens.push_back(path.substr(i + 1, close - i - 1));
      i = close + 1;
      after_bracket = true;
      if (i < path.size() && path[i] != '.' && path[i] != '[') return false;
    } else if (c == ']') {
      return false;
    } else {
      cur += c;
      after_bracket = false;
      ++i;
    }
  }
  if (!cur.empty()) tokens.push_back(cur);
  return !tokens.empty();
}

std::string trim(const std::string& s) {
  size_t b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return {};
  size_t e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

}  // namespace

void apply_override(nlohmann::json& root, const std::string& assignment, const std::string& origin,
                    const std::string& edit) {
  auto fail = [&](const std::string& message) {
    throw Error(
        fmt::format("{}: {}: {}", origin, edit.empty() ? "--set " + assignment : edit, message));
  };
  size_t eq = assignment.find('=');
  if (eq == std::string::npos) fail("expected key=value");
  const std::string path = trim(assignment.substr(0, eq));
  const std::string text = assignment.substr(eq + 1);
  std::vector<std::string> tokens;
  if (!split_path(path, tokens))
    fail(
        fmt::format("'{}' is not a key path like image.width or objects.0.material.opacity", path));

  nlohmann::json value;
  try {
    value = parse_strict_json(text, fmt::format("{}: --set {}", origin, path));
  } catch (const nlohmann::json::exception&) {
    value = text;  // not JSON: a bare word such as a method or object name
  }

  nlohmann::json* node = &root;
  std::string walked;
  for (size_t k = 0; k < tokens.size(); ++k) {
    const std::string& token = tokens[k];
    const bool last = k + 1 == tokens.size();
    if (node->is_null()) *node = nlohmann::json::object();  // created on the way down
    if (node->is_array()) {
      nlohmann::json* next = nullptr;
      if (is_index(token)) {
        size_t index = token.size() > 9 ? node->size() : std::stoul(token);
        if (index >= node->size())
          fail(fmt::format("{} has {} elements, there is no element {}", walked, node->size(),
                           token));
        next = &(*node)[index];
      } else {
        std::vector<std::string> names;
        for (nlohmann::json& element : *node) {
          if (!element.is_object() || !element.contains("name") || !element["name"].is_string())
            continue;
          names.push_back(element["name"].get<std::string>());
          if (names.back() == token && next == nullptr) next = &element;
        }
        if (next == nullptr)
          fail(fmt::format("{} has no element named '{}'{}", walked, token,
                           did_you_mean(token, names)));
      }
      if (last)
        *next = value;
      else
        node = next;
    } else if (node->is_object()) {
      if (last)
        (*node)[token] = value;
      else
        node = &(*node)[token];
    } else {
      fail(fmt::format("{} is a {}, not an object or array", walked, node->type_name()));
    }
    walked += walked.empty() ? token : (is_index(token) ? "[" + token + "]" : "." + token);
  }
}

}  // namespace imx::scene_json
