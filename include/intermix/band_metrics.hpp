// Intersection-aliasing metric (SPEC §9): PSNR restricted to a band of pixels around the curves
// where two objects intersect on screen.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "intermix/image.hpp"

namespace imx {

// The band around the intersection curves of two objects, from their first-hit depth images
// (depth in the red channel, +inf or NaN where the object is not hit): a pixel is on a curve
// where both objects are hit and the nearer one differs from a 4-neighbour's nearer one; the
// band is every pixel within `radius` pixels (Chebyshev) of such a pixel. Row-major, 1 = in.
// Throws imx::Error when the sizes differ.
std::vector<uint8_t> intersection_band(const Image& depth_a, const Image& depth_b, int radius);

// PSNR (display values, as psnr()) over the pixels where `mask` is non-zero; +inf when equal
// there, NaN when the mask is empty. Throws imx::Error on a size mismatch.
double masked_psnr(const Image& a, const Image& b, std::span<const uint8_t> mask);

}  // namespace imx
