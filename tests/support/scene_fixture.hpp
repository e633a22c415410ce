// Scenes for tests: the examples (whole, or shrunk to test sizes), scene JSON text built from
// small objects, and the parse and error capture the scene tests check it with.
#pragma once
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "expect_error.hpp"
#include "intermix/scene.hpp"

namespace imx::test {

// ---- the examples (examples/NAME.json)

// As a string, to go into command lines.
inline std::string example_scene(const std::string& name) {
  return std::string(IMX_EXAMPLES_DIR) + "/" + name + ".json";
}

// The overrides that make an example fast to render: a `pixels`-square image, and `voxels` per
// side for each of the named phantom volumes.
inline std::vector<std::string> small_example_overrides(int pixels,
                                                        const std::vector<std::string>& phantoms,
                                                        int voxels) {
  std::vector<std::string> overrides = {"image.width=" + std::to_string(pixels),
                                        "image.height=" + std::to_string(pixels)};
  for (const std::string& name : phantoms)
    overrides.push_back("objects." + name + ".source.size=" + std::to_string(voxels));
  return overrides;
}

// The example written to `folder` as small_example_overrides makes it, every phantom at `voxels`
// (to edit or save beside it); its path.
inline std::filesystem::path write_small_example(const std::filesystem::path& folder,
                                                 const std::string& name, int pixels, int voxels) {
  nlohmann::json scene = nlohmann::json::parse(std::ifstream(example_scene(name)));
  scene["image"]["width"] = pixels;
  scene["image"]["height"] = pixels;
  for (nlohmann::json& o : scene["objects"])
    if (o.contains("source") && o["source"].contains("phantom")) o["source"]["size"] = voxels;
  const std::filesystem::path file = folder / (name + ".json");
  std::ofstream(file) << scene.dump(2);
  return file;
}

// ---- scene JSON text, for the parser's checks (text, so that a test can put in anything)

// {"objects": [`objects`], `more`}: `more` the other top-level members, if any.
inline std::string with_objects(const std::string& objects, const std::string& more = "") {
  return R"({"objects": [)" + objects + "]" + (more.empty() ? "" : ", " + more) + "}";
}

// A cube phantom of 8 voxels named `name`, white and opaque from 100 up; `extra`: more keys.
inline std::string volume_json(const std::string& name, const std::string& extra = "") {
  return R"({"name": ")" + name +
         R"(", "type": "volume", "source": {"phantom": "cube", "size": 8},
             "transfer_function": {"points": [[0, 1, 1, 1, 0], [100, 1, 1, 1, 1]]})" +
         (extra.empty() ? "" : ", " + extra) + "}";
}

// A mesh named `name` of `source`'s keys (a sphere of radius 10 by default); `extra`: more keys.
inline std::string mesh_json(const std::string& name,
                             const std::string& source = R"("primitive": "sphere", "radius": 10)",
                             const std::string& extra = "") {
  return R"({"name": ")" + name + R"(", "type": "mesh", "source": {)" + source + "}" +
         (extra.empty() ? "" : ", " + extra) + "}";
}

inline const std::string kAxialPlane =
    R"({"name": "axial", "type": "plane", "center": [0, 0, 5], "normal": [0, 0, 1], "size": 50})";

// Volumes `a` and `b` (volume_json, with their extra keys), the closed meshes "ball" (a sphere)
// and "brick" (a box), the open "sheet" (a quad) and the plane "axial".
inline std::string shapes_objects(const std::string& a, const std::string& b,
                                  const std::string& a_extra = "",
                                  const std::string& b_extra = "") {
  return volume_json(a, a_extra) + ", " + volume_json(b, b_extra) + ", " + mesh_json("ball") +
         ", " + mesh_json("brick", R"("primitive": "box", "size": 20)") + ", " +
         mesh_json("sheet", R"("primitive": "quad", "size": 20)") + ", " + kAxialPlane;
}

// The unit cube as an ASCII PLY file, wound outward; `inward` winds every face the other way,
// `one_face_reversed` only the first.
inline std::string cube_ply(bool inward = false, bool one_face_reversed = false) {
  std::string s =
      "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
      "property float z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < 8; ++i)
    s += std::to_string(i & 1) + " " + std::to_string((i >> 1) & 1) + " " +
         std::to_string((i >> 2) & 1) + "\n";
  const int faces[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                            {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  for (int f = 0; f < 12; ++f) {
    const bool reverse = inward != (one_face_reversed && f == 0);
    const int* v = faces[f];
    s += "3 " + std::to_string(v[0]) + " " + std::to_string(reverse ? v[2] : v[1]) + " " +
         std::to_string(reverse ? v[1] : v[2]) + "\n";
  }
  return s;
}

// ---- scene documents, to write and load whole

// A volume object of `file`, drawn as a maximum intensity projection from black at 0 to white at
// `top`.
inline nlohmann::json mip_volume(const std::string& name, const std::filesystem::path& file,
                                 double top) {
  return {{"name", name},
          {"type", "volume"},
          {"source", {{"file", file.string()}}},
          {"style", "mip"},
          {"transfer_function", {{"points", {{0, 0, 0, 0, 0}, {top, 1, 1, 1, 1}}}}}};
}

// `objects` seen from `eye` towards `target`, z up, in a `pixels`-square image.
inline nlohmann::json scene_document(const std::vector<nlohmann::json>& objects, int pixels,
                                     glm::dvec3 eye, glm::dvec3 target) {
  return {{"camera",
           {{"eye", {eye.x, eye.y, eye.z}},
            {"target", {target.x, target.y, target.z}},
            {"up", {0, 0, 1}}}},
          {"image", {{"width", pixels}, {"height", pixels}}},
          {"objects", nlohmann::json(objects)}};
}

// ---- parsing

// A scene from JSON text, named "scene.json" in its errors.
inline Scene parse(const std::string& text, const std::vector<std::string>& overrides = {},
                   const std::filesystem::path& base_dir = {}) {
  return parse_scene(text, base_dir, "scene.json", overrides);
}

// The error parsing `text` gives, after checking that it is one line: a message per failure.
inline std::string parse_error(const std::string& text,
                               const std::vector<std::string>& overrides = {},
                               const std::filesystem::path& base_dir = {}) {
  std::string message = error_of([&] { parse(text, overrides, base_dir); });
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  return message;
}

}  // namespace imx::test
