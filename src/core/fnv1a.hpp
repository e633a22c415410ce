// Fnv1a: the 64-bit FNV-1a hash, the one content hash of the project (stage keys, transfer
// function fingerprints, image hashes in tests). Not for security: for telling content apart.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <type_traits>

namespace imx {

class Fnv1a {
 public:
  Fnv1a& add_bytes(const void* data, size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) h_ = (h_ ^ p[i]) * 0x100000001b3ULL;
    return *this;
  }
  // Plain values (numbers, glm vectors and matrices, enums, pointers) hash by their bytes.
  template <class T>
  Fnv1a& add(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &v, sizeof(T));
    return add_bytes(bytes, sizeof(T));
  }
  // The length first, so that ("ab", "c") and ("a", "bc") differ.
  Fnv1a& add(std::string_view s) {
    add(s.size());
    return add_bytes(s.data(), s.size());
  }
  uint64_t value() const { return h_; }

 private:
  uint64_t h_ = 0xcbf29ce484222325ULL;
};

}  // namespace imx
