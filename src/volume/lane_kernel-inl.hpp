// run_lane_kernel: the one dispatch of a vector-lane kernel (the packet marcher, the packet
// projection) on a volume's voxel type, per SIMD target. Pure: no allocation, no exceptions.
#if defined(IMX_VOLUME_LANE_KERNEL_INL_HPP_) == defined(HWY_TARGET_TOGGLE)
#ifdef IMX_VOLUME_LANE_KERNEL_INL_HPP_
#undef IMX_VOLUME_LANE_KERNEL_INL_HPP_
#else
#define IMX_VOLUME_LANE_KERNEL_INL_HPP_
#endif

#include <type_traits>

#include <hwy/highway.h>

#include "volume/prepared_volume.hpp"

HWY_BEFORE_NAMESPACE();
namespace imx::HWY_NAMESPACE {

// Runs Kernel<T, NoData>(v, grid, args...).run() for `v`'s voxel type T: the no-data variant
// (NaN and inf voxels are no data) only for a float volume that holds such voxels, so that
// other volumes never pay for its tests.
template <template <class, bool> class Kernel, class... Args>
void run_lane_kernel(const PreparedVolume& v, const Args&... args) {
  v.grid.visit([&](const auto& grid) HWY_ATTR {
    using T = std::remove_cvref_t<decltype(*grid.data)>;
    if constexpr (std::is_floating_point_v<T>) {
      if (v.has_no_data) {
        Kernel<T, true>(v, grid, args...).run();
        return;
      }
    }
    Kernel<T, false>(v, grid, args...).run();
  });
}

}  // namespace imx::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // IMX_VOLUME_LANE_KERNEL_INL_HPP_
