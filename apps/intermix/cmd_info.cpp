// intermix info FILE | --phantom NAME: what a volume or mesh holds.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "core/math.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"

namespace imx::cli {

namespace {

bool is_volume_file(const std::string& path) {
  std::string p = path;
  std::transform(p.begin(), p.end(), p.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const char* ext : {".nrrd", ".nhdr", ".nii", ".nii.gz", ".mha", ".mhd"})
    if (p.size() >= std::strlen(ext) &&
        p.compare(p.size() - std::strlen(ext), std::string::npos, ext) == 0)
      return true;
  return false;
}

nlohmann::json describe(const VolumeData& v) {
  auto [lo, hi] = v.range();
  glm::dvec3 s = v.spacing();
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 4; ++r)
    rows.push_back({v.index_to_world[0][r], v.index_to_world[1][r], v.index_to_world[2][r],
                    v.index_to_world[3][r]});
  glm::dvec3 lo_w(INFINITY), hi_w(-INFINITY);
  for (int c = 0; c < 8; ++c) {
    glm::dvec3 idx((c & 1) ? v.dims.x - 1 : 0, (c & 2) ? v.dims.y - 1 : 0,
                   (c & 4) ? v.dims.z - 1 : 0);
    glm::dvec3 w = transform_point(v.index_to_world, idx);
    lo_w = glm::min(lo_w, w);
    hi_w = glm::max(hi_w, w);
  }
  return {{"kind", "volume"},
          {"dims", {v.dims.x, v.dims.y, v.dims.z}},
          {"type", voxel_type_name(v.type())},
          {"spacing_mm", {s.x, s.y, s.z}},
          {"index_to_world", rows},
          {"world_bounds_mm", {{lo_w.x, lo_w.y, lo_w.z}, {hi_w.x, hi_w.y, hi_w.z}}},
          {"range", {lo, hi}}};
}

nlohmann::json describe(const Mesh& m) {
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const glm::vec3& p : m.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return {{"kind", "mesh"},
          {"vertices", m.positions.size()},
          {"triangles", m.triangles.size()},
          {"has_normals", !m.normals.empty()},
          {"bounds", {{lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z}}}};
}

void print_human(const nlohmann::json& j) {
  for (auto it = j.begin(); it != j.end(); ++it)
    std::printf("%-16s %s\n", it.key().c_str(), it.value().dump().c_str());
}

}  // namespace

Command add_info(CLI::App& app) {
  struct Options {
    std::string file, phantom;
    int size = 128;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option(
      "file", o->file,
      "volume (.nrrd, .nhdr, .nii, .nii.gz, .mha, .mhd) or mesh (.obj, .ply, .stl, ...)");
  app.add_option("--phantom", o->phantom, "describe a built-in phantom instead of a file");
  app.add_option("--size", o->size, "phantom size (voxels along the largest axis)");
  app.add_flag("--json", o->json, "print one JSON object on stdout");
  return [o]() {
    nlohmann::json j;
    if (!o->phantom.empty()) {
      j = describe(make_phantom(o->phantom, o->size));
      j["phantom"] = o->phantom;
    } else if (o->file.empty()) {
      throw Error("info: give a FILE or --phantom NAME");
    } else if (is_volume_file(o->file)) {
      j = describe(read_volume(o->file));
      j["file"] = o->file;
    } else {
      j = describe(read_mesh(o->file));
      j["file"] = o->file;
    }
    if (o->json)
      std::printf("%s\n", j.dump().c_str());
    else
      print_human(j);
    return 0;
  };
}

}  // namespace imx::cli
