// Small deterministic hashes for per-pixel seeds.
#pragma once
#include <cstdint>

namespace imx {

// A well-mixed 32-bit hash of a 32-bit value (lowbias32).
inline uint32_t hash_u32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

// A seed for pixel (x, y) and stream `s`, the same whatever the thread that renders it.
inline uint32_t pixel_seed(int x, int y, uint32_t s = 0) {
  return hash_u32(static_cast<uint32_t>(x) ^ hash_u32(static_cast<uint32_t>(y) ^ hash_u32(s)));
}

}  // namespace imx
