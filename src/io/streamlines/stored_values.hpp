// Numbers stored in either byte order, loaded from unaligned bytes: the tractogram readers'
// innermost loops, so the byte order is a template argument.
#pragma once
#include <bit>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace imx::detail {

template <class T, bool BigEndian>
inline T load_stored(const char* p) {
  static_assert(sizeof(T) == 2 || sizeof(T) == 4 || sizeof(T) == 8);
  using Bits = std::conditional_t<sizeof(T) == 2, uint16_t,
                                  std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>;
  Bits bits;
  std::memcpy(&bits, p, sizeof bits);
  if constexpr (BigEndian != (std::endian::native == std::endian::big)) {
    if constexpr (sizeof(T) == 2)
      bits = __builtin_bswap16(bits);
    else if constexpr (sizeof(T) == 4)
      bits = __builtin_bswap32(bits);
    else
      bits = __builtin_bswap64(bits);
  }
  return std::bit_cast<T>(bits);
}

template <class T>
inline T load_stored(const char* p, bool big_endian) {
  return big_endian ? load_stored<T, true>(p) : load_stored<T, false>(p);
}

}  // namespace imx::detail
