// Bounds on input geometry: within them every float product the renderer forms (squared
// distances, depths, plane equations) stays finite and keeps sub-micrometre precision.
#pragma once

namespace imx {

inline constexpr double kMaxCoordinateMm = 1e6;  // any world position: within 1 km of the origin
inline constexpr double kMaxLengthMm = 1e6;      // a size, spacing or distance
inline constexpr double kMinLengthMm = 1e-6;     // a nanometre
inline constexpr double kMaxScale = 1e6;         // a transform's stretch of one axis
inline constexpr double kMinScale = 1e-6;

}  // namespace imx
