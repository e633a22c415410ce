// Levels of detail for a render in bricks: each brick of a volume read from an OME-Zarr pyramid
// may read the coarsest level whose voxel still fits the pixels it covers, so that far or small
// bricks cost a fraction of their full-resolution voxels (docs/big_data.md, "Levels of detail").
#pragma once
#include <functional>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "intermix/scene.hpp"
#include "scene/scene_document.hpp"

namespace imx {

// One pyramid a volume object is read from: each level's grid and placement as the scene places
// the object (its transform included), level 0 the finest.
struct PyramidLevels {
  size_t object = 0;    // the object's index in Scene::order and in the document's "objects"
  int first_level = 0;  // the file's level that is index 0 here: the document's "level"
  std::vector<glm::ivec3> dims;
  std::vector<glm::dmat4> index_to_world;
};

// The pyramids of `outline`'s volume objects whose source is an OME-Zarr image of several levels
// (their headers only: one voxel is read per level).
std::vector<PyramidLevels> scene_pyramids(const SceneDocument& outline);

// The coarsest level of `pyramid` whose voxel's longest edge is at most `footprint` mm; 0 when
// none is.
int level_fitting(const PyramidLevels& pyramid, double footprint);

// The world box of level 0's voxel box `box` (half-open, voxel centres at integer indices).
void world_bounds(const PyramidLevels& pyramid, const VoxelBox& box, glm::dvec3& lo,
                  glm::dvec3& hi);

// Level `level`'s voxels covering level 0's `box` for trilinear sampling: the cells around its
// corners plus one voxel of apron, within the level's grid.
VoxelBox box_at_level(const PyramidLevels& pyramid, int level, const VoxelBox& box);

// How a render in bricks picks each brick's level: given the pyramid's object and the level
// that fits the brick's pixel footprint, the level to read. Empty: level 0 everywhere (full
// resolution).
using BrickLevelRule = std::function<int(size_t object, int fitting_level)>;

}  // namespace imx
