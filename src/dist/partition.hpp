// Partition: which part of a scene each of R processes renders (distributed rendering): whole
// objects dealt by estimated cost, or large volumes split into R bricks.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "intermix/scene.hpp"

namespace imx {

enum class PartitionMode : uint8_t { objects, bricks, automatic };

// "objects", "bricks" or "auto"; throws imx::Error naming the value otherwise.
PartitionMode parse_partition_mode(const std::string& name);
const char* partition_mode_name(PartitionMode mode);

// The part of one volume object a rank renders.
struct VolumeBrick {
  // Grid points it renders, lo..hi inclusive per axis: a piece of [0, dims - 1]. Neighbours
  // share their boundary plane, and each renders only its own side of it.
  glm::ivec3 lo{0}, hi{0};
  VoxelBox read;  // what it reads: lo..hi plus a one-voxel apron towards each neighbour
  // The planes at lo and hi where a neighbour begins, keeping this side (world space, from the
  // whole volume's placement, so both neighbours cut at the same t).
  std::vector<ClipPlane> bounds;
};

struct RankPart {
  std::vector<size_t> objects;                // Scene::order indices rendered whole here
  std::map<std::string, VolumeBrick> bricks;  // volume object name -> its brick here
  double cost = 0.0;                          // estimated, in voxel-sample units
};

struct Partition {
  PartitionMode mode = PartitionMode::objects;  // as chosen: never automatic
  std::vector<RankPart> ranks;

  // Rank r's part as one line, for the log.
  std::string describe(const Scene& scene, int rank) const;
};

// Volumes with fewer voxels than this are dealt whole even in bricks mode.
inline constexpr size_t kMinBrickedVoxels = size_t{48} * 48 * 48;

// Plans the parts of `scene` (volumes need only their placement and source_dims: a scene
// loaded with single-voxel regions will do) for `ranks` processes.
//  - objects: volumes (each with the planes that sample it), meshes and planes are dealt to the
//    least loaded rank, largest first.
//  - bricks: each volume of at least kMinBrickedVoxels voxels that no plane samples is cut into
//    `ranks` bricks by halving its longest world extent; the rest is dealt as in objects.
//  - automatic: objects when dealing them leaves no rank above 1.25 times the mean cost, else
//    bricks.
// Throws imx::Error for a scene with a csg block (not distributed yet).
Partition plan_partition(const Scene& scene, int ranks, PartitionMode mode);

// The brick of rank r's share `lo..hi` of a volume placed by `index_to_world` with `dims`
// voxels: its read box and its bounding planes.
VolumeBrick make_brick(glm::ivec3 lo, glm::ivec3 hi, glm::ivec3 dims,
                       const glm::dmat4& index_to_world);

}  // namespace imx
