// Evidence for a mesh file's space from the scene around it: a mesh that lies where the scene's
// volumes are only when mirrored (x and y negated: RAS read as LPS, or LPS as RAS) gets a note
// naming the fix. Placement never changes on this evidence alone.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "intermix/io.hpp"
#include "intermix/scene.hpp"

namespace imx::scene_json {

// A mesh object whose file's space the scene did not give ("space" in its source).
struct MeshSpaceCandidate {
  std::string name;                    // the object's
  std::string file;                    // the file's name, for the note
  MeshSpace read_as = MeshSpace::lps;  // how its coordinates were taken
  std::string why;                     // what chose that: "it names no space", "it says SPACE=RAS"
  std::shared_ptr<const Mesh> mesh;    // in LPS, before the object's transform
  glm::dmat4 transform{1.0};           // the object's
};

// How well a box of the mesh fits the volumes' box, as placed and mirrored.
struct MirrorEvidence {
  double inside = 0.0, inside_mirrored = 0.0;  // fraction of the mesh's box in the volumes' box
  double offset_mm = 0.0, offset_mirrored_mm = 0.0;  // box centre to the volumes' box centre
  bool mirrored_fits_far_better = false;
};

// The evidence for `candidate` among `volumes` (their voxel boxes in world space). Mirrored fits
// far better when the mirrored mesh is at least as much inside the volumes and either (a) it is
// mostly inside (>= 75%) where the placed one is mostly out (<= 25%), or (b) the mesh is an
// organ's size (its box at least half the volumes' box on every axis) and mirroring brings its
// centre three times closer to theirs, from 15 mm or more.
MirrorEvidence mirror_evidence(const MeshSpaceCandidate& candidate,
                               const std::vector<VolumeObject>& volumes);

// One note per candidate that mirrored fits far better, naming the space that would fit.
std::vector<std::string> mirrored_mesh_notes(const std::vector<MeshSpaceCandidate>& candidates,
                                             const std::vector<VolumeObject>& volumes);

}  // namespace imx::scene_json
