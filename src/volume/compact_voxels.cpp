#include "volume/compact_voxels.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace imx {
namespace {

struct ValueRange {
  float lo = std::numeric_limits<float>::infinity();
  float hi = -std::numeric_limits<float>::infinity();
  bool whole = true;  // every value finite and integral
};

ValueRange scan(const float* v, size_t n) {
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, n, 1 << 16), ValueRange{},
      [v](const tbb::blocked_range<size_t>& r, ValueRange acc) {
        if (!acc.whole) return acc;
        for (size_t i = r.begin(); i < r.end(); ++i) {
          const float x = v[i];
          // NaN and inf fail x == trunc(x) or the range check below.
          if (!(x == std::trunc(x))) return ValueRange{acc.lo, acc.hi, false};
          acc.lo = std::min(acc.lo, x);
          acc.hi = std::max(acc.hi, x);
        }
        return acc;
      },
      [](ValueRange a, const ValueRange& b) {
        return ValueRange{std::min(a.lo, b.lo), std::max(a.hi, b.hi), a.whole && b.whole};
      });
}

template <class T>
VoxelStorage convert(const float* v, size_t n) {
  std::vector<T> out(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 16),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i < r.end(); ++i) out[i] = static_cast<T>(v[i]);
                    });
  return VoxelBuffer<T>(std::move(out));
}

}  // namespace

std::optional<VoxelStorage> compact_integer_voxels(const VolumeData& data) {
  const auto* floats = std::get_if<VoxelBuffer<float>>(&data.voxels);
  if (floats == nullptr || data.colours || floats->size() == 0) return std::nullopt;
  const ValueRange r = scan(floats->data(), floats->size());
  if (!r.whole || !std::isfinite(r.lo) || !std::isfinite(r.hi)) return std::nullopt;
  if (r.lo >= -32768.0f && r.hi <= 32767.0f)
    return convert<int16_t>(floats->data(), floats->size());
  if (r.lo >= 0.0f && r.hi <= 65535.0f) return convert<uint16_t>(floats->data(), floats->size());
  return std::nullopt;
}

}  // namespace imx
