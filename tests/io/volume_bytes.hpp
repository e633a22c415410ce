// The bytes of hand-built volume files: voxel arrays as raw bytes, and gzip streams of them (as
// the project's writers compress).
#pragma once
#include <cstdint>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "io/streams/gzip.hpp"

namespace imx::test {

template <class T>
std::string raw_bytes(const std::vector<T>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

inline std::string gzipped(const std::string& bytes) {
  std::ostringstream out;
  detail::gzip(
      std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()), out,
      6, "test");
  return out.str();
}

}  // namespace imx::test
