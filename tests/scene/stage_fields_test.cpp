// The stage-hash decisions of scene/stage_fields.hpp: every field it hashes moves the hash, and
// every field it leaves out does not (a field added without a decision does not compile).
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "scene/stage_fields.hpp"

namespace imx {
namespace {

struct Change {
  std::string field;
  std::function<void(Scene&)> apply;
};

uint64_t volume_hash(const Scene& s) {
  Fnv1a h;
  hash_stage_fields(h, s, s.volumes[0]);
  return h.value();
}
uint64_t mesh_hash(const Scene& s) {
  Fnv1a h;
  hash_stage_fields(h, s.meshes[0]);
  return h.value();
}
uint64_t plane_hash(const Scene& s) {
  Fnv1a h;
  hash_stage_fields(h, s, s.planes[0]);
  return h.value();
}

// The same scene each call: its data and meshes are the same objects (hashed by identity).
Scene base() {
  static const auto data = std::make_shared<const VolumeData>();
  static const auto mesh = std::make_shared<const Mesh>();
  Scene s;
  VolumeObject v;
  v.name = "ct";
  v.data = data;
  v.transfer_function.points = {{0.0, glm::vec4(0.0f)}, {1.0, glm::vec4(1.0f)}};
  s.volumes.push_back(v);
  MeshObject m;
  m.name = "ball";
  m.mesh = mesh;
  s.meshes.push_back(m);
  PlaneObject p;
  p.name = "axial";
  p.volume = 0;
  s.planes.push_back(p);
  return s;
}

void expect_moves(const std::function<uint64_t(const Scene&)>& hash,
                  const std::vector<Change>& changes, bool moves) {
  const uint64_t before = hash(base());
  for (const Change& c : changes) {
    Scene s = base();
    c.apply(s);
    if (moves)
      EXPECT_NE(hash(s), before) << c.field << " is hashed but does not change the key";
    else
      EXPECT_EQ(hash(s), before) << c.field << " is declared unread but changes the key";
  }
}

TEST(StageFields, EveryHashedVolumeFieldMovesTheKeyAndNoOtherDoes) {
  auto v = [](Scene& s) -> VolumeObject& { return s.volumes[0]; };
  expect_moves(
      volume_hash,
      {{"data", [&](Scene& s) { v(s).data = std::make_shared<const VolumeData>(); }},
       {"index_to_world", [&](Scene& s) { v(s).index_to_world[3][0] = 1.0; }},
       {"transfer_function", [&](Scene& s) { v(s).transfer_function.points[1].rgba.a = 0.5f; }},
       {"unit_distance", [&](Scene& s) { v(s).transfer_function.unit_distance = 2.0; }},
       {"style", [&](Scene& s) { v(s).style = VolumeStyle::mip; }},
       {"iso_value", [&](Scene& s) { v(s).iso_value = 3.0; }},
       {"xray_mode", [&](Scene& s) { v(s).xray_mode = XrayMode::average; }},
       {"shading", [&](Scene& s) { v(s).shading.specular = 0.7f; }},
       {"clip_planes", [&](Scene& s) { v(s).clip_planes.push_back({}); }},
       {"clip_meshes",
        [&](Scene& s) {
          v(s).clip_meshes.push_back({0, true});
        }}},
      true);
  expect_moves(volume_hash,
               {{"name", [&](Scene& s) { v(s).name = "other"; }},
                {"display_window", [&](Scene& s) { v(s).display_window = glm::dvec2(40, 400); }},
                {"window", [&](Scene& s) { v(s).window = glm::dvec2(400, 1800); }},
                {"units", [&](Scene& s) { v(s).units = "HU"; }},
                {"source_dims", [&](Scene& s) { v(s).source_dims = glm::ivec3(4); }},
                {"frame", [&](Scene& s) { v(s).frame = 2; }},
                {"frames", [&](Scene& s) { v(s).frames = 3; }}},
               false);
}

TEST(StageFields, EveryHashedMeshAndPlaneFieldMovesTheKey) {
  auto m = [](Scene& s) -> MeshObject& { return s.meshes[0]; };
  expect_moves(mesh_hash,
               {{"mesh", [&](Scene& s) { m(s).mesh = std::make_shared<const Mesh>(); }},
                {"material.color", [&](Scene& s) { m(s).material.color.r = 0.5f; }},
                {"material.opacity", [&](Scene& s) { m(s).material.opacity = 0.5f; }},
                {"material.shading", [&](Scene& s) { m(s).material.shading.enabled = false; }},
                {"thickness", [&](Scene& s) { m(s).thickness = 2.0; }},
                {"interior", [&](Scene& s) { m(s).interior = MeshInterior{}; }}},
               true);
  expect_moves(mesh_hash, {{"name", [&](Scene& s) { m(s).name = "other"; }}}, false);
  auto p = [](Scene& s) -> PlaneObject& { return s.planes[0]; };
  expect_moves(plane_hash,
               {{"center", [&](Scene& s) { p(s).center.x = 1.0; }},
                {"normal", [&](Scene& s) { p(s).normal = glm::dvec3(1, 0, 0); }},
                {"up", [&](Scene& s) { p(s).up = glm::dvec3(0, 0, 1); }},
                {"size", [&](Scene& s) { p(s).size.x = 10.0; }},
                {"volume", [&](Scene& s) { p(s).volume = -1; }},
                {"window", [&](Scene& s) { p(s).window.y = 10.0; }},
                {"color", [&](Scene& s) { p(s).color.g = 0.0f; }},
                {"colormap", [&](Scene& s) { p(s).colormap = Colormap::hot; }},
                {"threshold", [&](Scene& s) { p(s).threshold = 3.0; }},
                {"symmetric", [&](Scene& s) { p(s).symmetric = true; }},
                {"opacity", [&](Scene& s) { p(s).opacity = 0.5f; }},
                {"thickness", [&](Scene& s) { p(s).thickness = 1.0; }},
                {"the volume's data",
                 [&](Scene& s) { s.volumes[0].data = std::make_shared<const VolumeData>(); }}},
               true);
  expect_moves(plane_hash,
               {{"name", [&](Scene& s) { p(s).name = "other"; }},
                {"the volume's transfer function",
                 [&](Scene& s) { s.volumes[0].transfer_function.points[0].value = -5.0; }}},
               false);
}

// A label map is hashed by content: every field a render reads moves both keys (the volume's, and
// a plane's that shows it), a label's name does not.
TEST(StageFields, ALabelMapMovesTheVolumeAndPlaneKeysButNotItsNames) {
  auto labelled = [](const std::function<void(LabelMap&)>& edit) {
    Scene s = base();
    auto m = std::make_shared<LabelMap>();
    m->entries = {{1, "csf", glm::vec3(0, 0, 1), 1.0f, true}};
    edit(*m);
    s.volumes[0].labels = m;
    return s;
  };
  const std::vector<std::pair<std::string, std::function<void(LabelMap&)>>> edits = {
      {"value", [](LabelMap& m) { m.entries[0].value = 2; }},
      {"color", [](LabelMap& m) { m.entries[0].color.r = 1.0f; }},
      {"opacity", [](LabelMap& m) { m.entries[0].opacity = 0.5f; }},
      {"visible", [](LabelMap& m) { m.entries[0].visible = false; }},
      {"entries",
       [](LabelMap& m) {
         m.entries.push_back({3, "gm", glm::vec3(1), 1.0f, true});
       }},
      {"palette_unlisted", [](LabelMap& m) { m.palette_unlisted = false; }},
      {"interpolation", [](LabelMap& m) { m.interpolation = LabelInterpolation::nearest; }},
      {"unit_distance", [](LabelMap& m) { m.unit_distance = 2.0; }},
      {"shown", [](LabelMap& m) { m.shown = false; }}};
  for (auto hash : {volume_hash, plane_hash}) {
    const uint64_t before = hash(labelled([](LabelMap&) {}));
    EXPECT_NE(before, hash(base())) << "a label map";
    for (const auto& [field, edit] : edits) EXPECT_NE(hash(labelled(edit)), before) << field;
    EXPECT_EQ(hash(labelled([](LabelMap& m) { m.entries[0].name = "other"; })), before);
  }
}

}  // namespace
}  // namespace imx
