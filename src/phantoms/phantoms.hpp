// The built-in phantom volumes, one maker per phantom (make_phantom checks names and sizes).
#pragma once
#include <functional>

#include "intermix/io.hpp"
#include "intermix/volume.hpp"

namespace imx::detail {

// One phantom at one size: its grid, and the voxels of any box of it, so that a box is made
// without the whole (make_phantom_region) and the grid without any voxels (phantom_header).
struct Phantom {
  VolumeHeader header;
  // The voxels of `box`, already checked to lie inside header.dims, placed where they lie.
  std::function<VolumeData(const VoxelBox& box)> sample;
};

// `size` is the voxel count along the largest axis, already checked to lie in [8, 1024].

// int16 CT-like head (HU): air, skin, skull with cortical tables, brain, ventricles, eyes, nose.
Phantom ct_head_phantom(int size);
// uint8 solid cube (255 inside, 0 outside) spanning 60% of a 128 mm grid.
Phantom cube_phantom(int size);
// uint8 solid ellipsoid, semi-axes (45, 30, 35) mm, on a 0.8 mm grid at size 128.
Phantom ellipsoid_phantom(int size);
// float32 PET-like uptake on a coarse, rotated grid covering the ct-head's head.
Phantom pet_phantom(int size);
// float32 nested spherical shells; shell i (0 = innermost) has value 10 * (i + 1).
Phantom shells_phantom(int size);
// float32 signed distance R - |p| (mm, positive inside) of a sphere of radius 44.8 mm.
Phantom sphere_phantom(int size);

}  // namespace imx::detail
