// The built-in phantom volumes, one maker per phantom (make_phantom checks names and sizes).
#pragma once
#include "intermix/volume.hpp"

namespace imx::detail {

// `size` is the voxel count along the largest axis, already checked to lie in [8, 1024].

// int16 CT-like head (HU): air, skin, skull with cortical tables, brain, ventricles, eyes, nose.
VolumeData make_ct_head(int size);
// uint8 solid cube (255 inside, 0 outside) spanning 60% of a 128 mm grid.
VolumeData make_cube(int size);
// uint8 solid ellipsoid, semi-axes (45, 30, 35) mm, on a 0.8 mm grid at size 128.
VolumeData make_ellipsoid(int size);
// float32 PET-like uptake on a coarse, rotated grid covering the ct-head's head.
VolumeData make_pet(int size);
// float32 nested spherical shells; shell i (0 = innermost) has value 10 * (i + 1).
VolumeData make_shells(int size);
// float32 signed distance R - |p| (mm, positive inside) of a sphere of radius 44.8 mm.
VolumeData make_sphere(int size);

}  // namespace imx::detail
