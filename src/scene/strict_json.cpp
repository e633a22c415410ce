#include "scene/strict_json.hpp"

#include <set>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx::scene_json {
namespace {

// One open object or array while parsing: where it is, and what it has seen so far.
struct Open {
  bool array = false;
  long index = -1;             // arrays: the element being read
  std::string key;             // objects: the key being read
  std::set<std::string> keys;  // objects: every key read
};

// The path of the innermost open value, "objects[2].material" in the JsonReader style: each
// enclosing value contributes the key or index it is reading.
std::string path_of(const std::vector<Open>& open) {
  std::string path;
  for (const Open& o : open) {
    if (&o == &open.back()) break;  // its own key is not part of its path
    if (o.array)
      path += fmt::format("[{}]", o.index);
    else
      path += (path.empty() ? "" : ".") + o.key;
  }
  return path;
}

}  // namespace

nlohmann::json parse_strict_json(const std::string& text, const std::string& origin) {
  std::vector<Open> open;
  // An element of an array starts: count it.
  auto element = [&] {
    if (!open.empty() && open.back().array) ++open.back().index;
  };
  const nlohmann::json::parser_callback_t check = [&](int, nlohmann::json::parse_event_t event,
                                                      nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    switch (event) {
      case Event::object_start:
      case Event::array_start:
        element();
        if (static_cast<int>(open.size()) >= kMaxJsonDepth)
          throw Error(fmt::format("{}: JSON nested deeper than {} levels", origin, kMaxJsonDepth));
        open.push_back({event == Event::array_start, -1, {}, {}});
        break;
      case Event::object_end:
      case Event::array_end:
        open.pop_back();
        break;
      case Event::key: {
        Open& o = open.back();
        o.key = parsed.get<std::string>();
        if (!o.keys.insert(o.key).second) {
          const std::string where = path_of(open);
          throw Error(fmt::format("{}: {}key '{}' appears twice in the same object", origin,
                                  where.empty() ? "" : where + ": ", o.key));
        }
        break;
      }
      case Event::value:
        element();
        break;
    }
    return true;
  };
  return nlohmann::json::parse(text, check);
}

}  // namespace imx::scene_json
