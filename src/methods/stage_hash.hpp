// StageHash: a 64-bit FNV-1a hash of what a pipeline stage reads, the key of its kept output.
#pragma once
#include <cstdint>
#include <cstring>
#include <string_view>
#include <type_traits>

namespace imx {

class StageHash {
 public:
  // Plain values (numbers, glm vectors and matrices, enums, pointers) hash by their bytes.
  template <class T>
  StageHash& add(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &v, sizeof(T));
    for (unsigned char b : bytes) mix(b);
    return *this;
  }
  StageHash& add(std::string_view s) {
    add(s.size());
    for (char c : s) mix(static_cast<unsigned char>(c));
    return *this;
  }
  uint64_t value() const { return h_; }

 private:
  void mix(unsigned char b) {
    h_ ^= b;
    h_ *= 0x100000001b3ULL;
  }
  uint64_t h_ = 0xcbf29ce484222325ULL;
};

}  // namespace imx
