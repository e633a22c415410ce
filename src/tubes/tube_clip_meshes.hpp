// TubeClipMeshes: the closed meshes that clip a streamline object ("clip", as a volume's clip
// meshes), and the pieces of a ray they keep, with the mesh's normal at each cut for its cap.
#pragma once
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/ray.hpp"
#include "csg/clip_state.hpp"
#include "intermix/mesh.hpp"
#include "intermix/scene.hpp"
#include "volume/kept_span.hpp"

namespace imx {

class TubeClipMeshes {
 public:
  // A ray meeting the meshes more often than this keeps nothing (a pathological cutter).
  static constexpr int kMaxCrossings = 64;

  // One end of a kept piece: where it lies and, when a mesh cuts the ray there, the mesh's unit
  // normal turned to face out of the kept piece (toward the eye at its start, away at its end).
  struct End {
    float t = 0.0f;
    bool cut = false;
    glm::vec3 normal{0.0f};
  };
  struct Piece {
    End lo, hi;
  };
  // The pieces of a ray every mesh keeps, sorted and disjoint; the last may end at infinity.
  struct Pieces {
    int count = 0;
    Piece piece[kMaxClipPieces];
  };

  // `meshes` are world-space closed meshes wound outward (the scene loader turns them so);
  // `keep_inside[i]`: mesh i keeps its inside (probing), else its outside (cutting). Throws
  // imx::Error naming the object for a triangle naming a vertex it does not have.
  TubeClipMeshes(std::vector<std::shared_ptr<const Mesh>> meshes, std::vector<bool> keep_inside,
                 const std::string& object);
  ~TubeClipMeshes();
  TubeClipMeshes(const TubeClipMeshes&) = delete;
  TubeClipMeshes& operator=(const TubeClipMeshes&) = delete;

  // The pieces of `ray` in [0, inf) that every mesh keeps. Pure, no allocation. Thread-safe.
  void kept(const Ray& ray, Pieces& out) const;

  size_t mesh_count() const { return meshes_.size(); }
  const Mesh& mesh(size_t i) const { return *meshes_[i]; }
  bool keeps_inside(size_t i) const { return (rule_.ones >> i) & 1u; }

 private:
  struct Bvh;
  std::unique_ptr<Bvh> bvh_;
  std::vector<std::shared_ptr<const Mesh>> meshes_;  // held: the cache keys them by address
  ClipState rule_;                                   // digit 1: keep inside, digit 0: outside
};

// The clip meshes of `object` resolved in `meshes` (the scene's), built now; null without any.
// Throws imx::Error naming the object for an index that is not one of `meshes`.
std::shared_ptr<const TubeClipMeshes> make_tube_clip_meshes(const StreamlineObject& object,
                                                            std::span<const MeshObject> meshes);

}  // namespace imx
