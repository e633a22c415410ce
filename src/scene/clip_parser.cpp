// Parser for the "clip" lists of volumes and streamline objects: closed meshes that keep what
// lies inside or outside them.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/edit_distance.hpp"
#include "io/mesh/mesh_topology.hpp"
#include "scene/scene_parsers.hpp"

namespace imx::scene_json {
namespace {

constexpr size_t kMaxClipMeshes = 64;  // one winding each per ray (frame/clip_intervals.hpp)

std::string plural(size_t n, const char* word) {
  return fmt::format("{} {}{}", n, word, n == 1 ? "" : "s");
}

}  // namespace

void parse_clip_meshes(const std::vector<JsonReader>& objects, Scene& scene) {
  std::vector<std::string> names;
  std::map<std::string, ObjectRef> by_name;
  for (const ObjectRef& ref : scene.order) {
    const std::string& name = object_name(scene, ref);
    names.push_back(name);
    by_name.emplace(name, ref);
  }
  std::vector<bool> admitted(scene.meshes.size(), false);
  size_t distinct = 0;
  for (size_t i = 0; i < scene.order.size() && i < objects.size(); ++i) {
    // Volumes and streamline objects take clip meshes (a connectome's parser refuses "clip").
    const ObjectRef owner = scene.order[i];
    if (owner.kind != ObjectKind::volume && owner.kind != ObjectKind::streamlines) continue;
    std::optional<JsonReader> list = objects[i].find("clip");
    if (!list) continue;
    list->expect_array();
    std::vector<ClipMesh>& clips = owner.kind == ObjectKind::volume
                                       ? scene.volumes[owner.index].clip_meshes
                                       : scene.streamlines[owner.index].clip_meshes;
    const std::string owner_name =
        fmt::format("{} '{}'", owner.kind == ObjectKind::volume ? "volume" : "streamlines",
                    object_name(scene, owner));
    std::map<int, size_t> seen;  // mesh -> its position in this list
    for (size_t j = 0; j < list->size(); ++j) {
      const JsonReader entry = list->at(j);
      entry.expect_object();
      entry.check_keys({"mesh", "keep"});
      const JsonReader mesh_at = entry.get("mesh");
      const std::string name = mesh_at.string();
      const bool keep_inside = entry.get("keep").choice({"inside", "outside"}) == "inside";
      auto found = by_name.find(name);
      if (found == by_name.end())
        mesh_at.fail(fmt::format("no object named '{}'{}", name, did_you_mean(name, names)));
      if (found->second.kind != ObjectKind::mesh)
        mesh_at.fail(fmt::format("'{}' is a {}; clip geometry is a closed mesh", name,
                                 object_kind_name(found->second.kind)));
      const int m = found->second.index;
      if (auto [it, fresh] = seen.emplace(m, j); !fresh)
        mesh_at.fail(fmt::format("'{}' is already clip[{}] of {}", name, it->second, owner_name));
      if (!admitted[m]) {
        if (distinct == kMaxClipMeshes)
          mesh_at.fail(fmt::format("at most {} different clip meshes in a scene; '{}' is the {}th",
                                   kMaxClipMeshes, name, kMaxClipMeshes + 1));
        MeshObject& mesh = scene.meshes[m];
        const MeshTopology topology = check_closed(*mesh.mesh);
        if (topology.open_edges > 0)
          mesh_at.fail(fmt::format("mesh '{}' is not closed: {} (clip geometry needs an inside)",
                                   name, plural(topology.open_edges, "open edge")));
        if (topology.unpaired_edges > 0)
          mesh_at.fail(fmt::format("mesh '{}' is not consistently wound: {} without its reverse",
                                   name, plural(topology.unpaired_edges, "directed edge")));
        // Inside is where the winding is positive: an inward-facing mesh is turned outward. Each
        // MeshObject owns the mesh its transform produced, so this flips no other object.
        if (topology.signed_volume < 0.0)
          mesh.mesh = std::make_shared<const Mesh>(flipped(*mesh.mesh));
        admitted[m] = true;
        ++distinct;
      }
      clips.push_back(ClipMesh{m, keep_inside});
    }
  }
}

}  // namespace imx::scene_json
