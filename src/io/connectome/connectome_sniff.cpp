// A one-pass scan of a JSON prefix that keeps only the keys that tell a connectome: those of the
// top-level object, and those inside its "nodes" value. Malformed text says "no".
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "io/connectome/jcon.hpp"

namespace imx::detail {
namespace {

constexpr size_t kMaxDepth = 64;

// Keys inside "nodes" that only a connectome's nodes have (dense and sparse layouts).
constexpr std::array<std::string_view, 6> kNodeKeys = {"names", "X",          "Color",
                                                       "Size",  "colorValue", "sizeValue"};
// NiiVue's display fields, found at the top level of its connectomes only.
constexpr std::array<std::string_view, 6> kStyleKeys = {"nodeColormap", "nodeScale", "nodeMinColor",
                                                        "edgeColormap", "edgeScale", "edgeMin"};

template <size_t N>
bool is_one_of(std::string_view key, const std::array<std::string_view, N>& keys) {
  for (std::string_view k : keys)
    if (key == k) return true;
  return false;
}

struct Frame {
  bool object = false;
  bool in_nodes = false;  // the top level's "nodes" value, or inside it
};

struct Findings {
  bool nodes = false, edges = false, style = false, node_keys = false, point_set = false;
};

// The string starting at head[at] (a quote); npos where the head ends inside it. Escapes are
// kept as written: the keys looked for have none.
size_t string_end(std::string_view head, size_t at) {
  for (size_t i = at + 1; i < head.size(); ++i) {
    if (head[i] == '\\')
      ++i;
    else if (head[i] == '"')
      return i;
  }
  return std::string_view::npos;
}

bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

// Scans `head`; false where it is not the start of a JSON object.
bool scan(std::string_view head, Findings& found) {
  if (head.substr(0, 3) == "\xEF\xBB\xBF") head.remove_prefix(3);  // UTF-8 byte order mark
  size_t at = 0;
  while (at < head.size() && is_blank(head[at])) ++at;
  if (at == head.size() || head[at] != '{') return false;
  std::vector<Frame> stack;
  std::string_view last_key;  // the last key of the top-level object
  bool after_fs_data_type = false;
  for (; at < head.size(); ++at) {
    const char c = head[at];
    if (c == '{' || c == '[') {
      if (stack.size() >= kMaxDepth) return false;
      const bool in_nodes =
          !stack.empty() && (stack.back().in_nodes || (stack.size() == 1 && last_key == "nodes"));
      stack.push_back({c == '{', in_nodes});
    } else if (c == '}' || c == ']') {
      if (stack.empty() || stack.back().object != (c == '}')) return false;
      stack.pop_back();
      if (stack.empty()) return true;  // the whole document was seen
    } else if (c == '"') {
      const size_t end = string_end(head, at);
      if (end == std::string_view::npos) return true;  // the head ends inside a string
      const std::string_view text = head.substr(at + 1, end - at - 1);
      size_t next = end + 1;
      while (next < head.size() && is_blank(head[next])) ++next;
      const bool key = next < head.size() && head[next] == ':' && stack.back().object;
      if (key && stack.size() == 1) {
        last_key = text;
        found.nodes |= text == "nodes";
        found.edges |= text == "edges";
        found.style |= is_one_of(text, kStyleKeys);
        after_fs_data_type = text == "data_type";
      } else if (key && stack.back().in_nodes) {
        found.node_keys |= is_one_of(text, kNodeKeys);
      } else if (!key && stack.size() == 1 && after_fs_data_type) {
        found.point_set |= text == "fs_pointset";
      }
      at = end;
    }
  }
  return true;  // the head ends inside the document
}

}  // namespace

bool looks_like_connectome_json(std::string_view head) {
  Findings found;
  if (!scan(head, found)) return false;
  return found.point_set || (found.nodes && (found.edges || found.node_keys || found.style));
}

}  // namespace imx::detail
