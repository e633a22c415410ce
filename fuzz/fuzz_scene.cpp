// Scene files through load_scene: strict JSON, --set overrides, every object parser, CSG
// normalization. The input is the scene text; after a 0x00 byte, each further 0x00-separated
// piece is one --set override "key=value".
//
// To keep one run fast, built-in phantoms are held to kMaxPhantom voxels along their largest
// axis (a source without "size" would be 128) and primitive meshes to kMaxSegments segments:
// sources are rewritten before loading, when the text parses as JSON. Everything else reaches
// the loader exactly as fuzzed.
#include <exception>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness.hpp"
#include "intermix/scene.hpp"

namespace {

constexpr int kMaxPhantom = 24;
constexpr int kMaxSegments = 48;
constexpr int kWalkDepth = 32;
// The loader refuses deeper nesting before anything else; deeper text is passed on as it is.
constexpr int kRewriteDepth = 1024;

using Json = nlohmann::ordered_json;

bool too_big(const Json& v, int limit) {
  return v.is_number() && !(v.get<double>() <= limit);
}

// Clamps phantom sizes and primitive segments in `j`; returns whether anything changed.
bool limit(Json& j, int depth) {
  if (depth > kWalkDepth) return false;
  bool changed = false;
  if (j.is_object()) {
    if (j.contains("phantom")) {
      auto it = j.find("size");
      if (it == j.end() || too_big(*it, kMaxPhantom)) {
        j["size"] = kMaxPhantom;
        changed = true;
      }
    }
    if (auto it = j.find("segments"); it != j.end() && too_big(*it, kMaxSegments)) {
      *it = kMaxSegments;
      changed = true;
    }
    for (auto& [key, value] : j.items()) changed = limit(value, depth + 1) || changed;
  } else if (j.is_array()) {
    for (Json& value : j) changed = limit(value, depth + 1) || changed;
  }
  return changed;
}

// Deepest [ / { nesting of JSON-ish text, outside strings.
int nesting(const std::string& text) {
  int depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (char c : text) {
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}

// The scene text with its sources limited (unchanged when nothing needed it or it is not JSON).
std::string limit_scene(std::string text) {
  if (nesting(text) > kRewriteDepth) return text;
  Json j = Json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return text;
  if (!limit(j, 0)) return text;
  return j.dump();
}

// The override with its value limited like the scene's sources.
std::string limit_override(const std::string& assignment) {
  size_t eq = assignment.find('=');
  if (eq == std::string::npos) return assignment;
  const std::string key = assignment.substr(0, eq);
  const std::string value = assignment.substr(eq + 1);
  if (nesting(value) > kRewriteDepth) return assignment;
  Json j = Json::parse(value, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return assignment;
  auto ends_with = [&](const std::string& s) {
    return key.size() >= s.size() && key.compare(key.size() - s.size(), s.size(), s) == 0;
  };
  if (ends_with("size") && too_big(j, kMaxPhantom)) return key + "=" + std::to_string(kMaxPhantom);
  if (ends_with("segments") && too_big(j, kMaxSegments))
    return key + "=" + std::to_string(kMaxSegments);
  if (!limit(j, 0)) return assignment;
  return key + "=" + j.dump();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  std::string_view input = as_view(data, size);
  size_t nul = input.find('\0');
  std::string text(input.substr(0, nul));
  std::vector<std::string> overrides;
  while (nul != std::string_view::npos) {
    input.remove_prefix(nul + 1);
    nul = input.find('\0');
    overrides.push_back(limit_override(std::string(input.substr(0, nul))));
  }
  std::filesystem::path file = dir.write("scene.json", limit_scene(std::move(text)));
  try {
    imx::Scene scene = imx::load_scene(file, overrides);
    accepted("scene");
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
