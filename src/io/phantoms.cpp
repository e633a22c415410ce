#include <fmt/format.h>
#include <fmt/ranges.h>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/phantoms.hpp"

namespace imx {

namespace {

constexpr int kMinSize = 8, kMaxSize = 1024;

struct Phantom {
  const char* name;
  VolumeData (*make)(int size);
};

constexpr Phantom kPhantoms[] = {
    {"ct-head", detail::make_ct_head},     {"cube", detail::make_cube},
    {"ellipsoid", detail::make_ellipsoid}, {"pet", detail::make_pet},
    {"shells", detail::make_shells},       {"sphere", detail::make_sphere}};

}  // namespace

std::vector<std::string> phantom_names() {
  std::vector<std::string> names;
  for (const Phantom& p : kPhantoms) names.emplace_back(p.name);
  return names;
}

VolumeData make_phantom(const std::string& name, int size) {
  for (const Phantom& p : kPhantoms) {
    if (name != p.name) continue;
    if (size < kMinSize || size > kMaxSize)
      throw Error(fmt::format("phantom '{}': size {} is out of range [{}, {}]", name, size,
                              kMinSize, kMaxSize));
    return p.make(size);
  }
  throw Error(
      fmt::format("unknown phantom '{}' (available: {})", name, fmt::join(phantom_names(), ", ")));
}

}  // namespace imx
