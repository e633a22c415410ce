// Whether two images are the same bytes: the tests of "nothing changed" (a reused frame, an
// edit that should not show, a hidden object).
#pragma once
#include <cstring>

#include <glm/vec4.hpp>

#include "intermix/image.hpp"

namespace imx::test {

inline bool same_bytes(const Image& a, const Image& b) {
  return a.width() == b.width() && a.height() == b.height() &&
         std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec4)) == 0;
}

}  // namespace imx::test
