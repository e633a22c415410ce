#include "scene/mesh_space_evidence.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "core/math.hpp"

namespace imx::scene_json {

namespace {

struct Box {
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
  void add(const glm::dvec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  bool empty() const { return !(lo.x <= hi.x); }
  glm::dvec3 centre() const { return 0.5 * (lo + hi); }
  // Sides of at least 1 mm, so that a flat mesh (a plane of points) still has a volume.
  glm::dvec3 size() const { return glm::max(hi - lo, glm::dvec3(1.0)); }
};

// The world box of every volume's voxels (half a voxel beyond the centres).
Box volumes_box(const std::vector<VolumeObject>& volumes) {
  Box box;
  for (const VolumeObject& v : volumes) {
    if (!v.data) continue;
    const glm::dvec3 d = glm::dvec3(v.data->dims) - 0.5;
    for (int c = 0; c < 8; ++c)
      box.add(transform_point(v.index_to_world,
                              {(c & 1) ? d.x : -0.5, (c & 2) ? d.y : -0.5, (c & 4) ? d.z : -0.5}));
  }
  return box;
}

// The fraction of `mesh`'s box inside `volumes`.
double inside(const Box& mesh, const Box& volumes) {
  const glm::dvec3 size = mesh.size();
  const glm::dvec3 centre = mesh.centre();
  const glm::dvec3 lo = glm::max(centre - 0.5 * size, volumes.lo);
  const glm::dvec3 hi = glm::min(centre + 0.5 * size, volumes.hi);
  const glm::dvec3 overlap = glm::max(hi - lo, glm::dvec3(0.0));
  return overlap.x * overlap.y * overlap.z / (size.x * size.y * size.z);
}

}  // namespace

MirrorEvidence mirror_evidence(const MeshSpaceCandidate& candidate,
                               const std::vector<VolumeObject>& volumes) {
  MirrorEvidence e;
  const Box around = volumes_box(volumes);
  if (around.empty() || !candidate.mesh || candidate.mesh->positions.empty()) return e;
  Box placed, mirrored;
  for (const glm::vec3& p : candidate.mesh->positions) {
    placed.add(transform_point(candidate.transform, glm::dvec3(p)));
    mirrored.add(transform_point(candidate.transform, glm::dvec3(-p.x, -p.y, p.z)));
  }
  e.inside = inside(placed, around);
  e.inside_mirrored = inside(mirrored, around);
  e.offset_mm = glm::length(placed.centre() - around.centre());
  e.offset_mirrored_mm = glm::length(mirrored.centre() - around.centre());
  const glm::dvec3 share = placed.size() / around.size();
  const bool organ_sized = std::min({share.x, share.y, share.z}) >= 0.5;
  const bool mostly_in = e.inside_mirrored >= 0.75 && e.inside <= 0.25;
  const bool centred =
      organ_sized && e.offset_mm >= 15.0 && e.offset_mirrored_mm * 3.0 <= e.offset_mm;
  e.mirrored_fits_far_better = e.inside_mirrored >= e.inside && (mostly_in || centred);
  return e;
}

std::vector<std::string> mirrored_mesh_notes(const std::vector<MeshSpaceCandidate>& candidates,
                                             const std::vector<VolumeObject>& volumes) {
  std::vector<std::string> notes;
  for (const MeshSpaceCandidate& c : candidates) {
    const MirrorEvidence e = mirror_evidence(c, volumes);
    if (!e.mirrored_fits_far_better) continue;
    const MeshSpace other = c.read_as == MeshSpace::ras ? MeshSpace::lps : MeshSpace::ras;
    notes.push_back(fmt::format(
        "mesh '{}': {} was read as {} ({}), where its box is {:.0f}% inside the volumes and its "
        "centre {:.0f} mm from theirs; read as {} (x and y mirrored) it would be {:.0f}% inside, "
        "{:.0f} mm from their centre. If it was written in {}, give its source \"space\": "
        "\"{}\" (on the command line: --set objects.{}.source.space={}); it is placed as read",
        c.name, c.file, mesh_space_name(c.read_as), c.why, 100.0 * e.inside, e.offset_mm,
        mesh_space_name(other), 100.0 * e.inside_mirrored, e.offset_mirrored_mm,
        mesh_space_name(other), mesh_space_name(other), c.name, mesh_space_name(other)));
  }
  return notes;
}

}  // namespace imx::scene_json
