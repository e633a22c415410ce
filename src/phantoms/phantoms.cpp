#include <fmt/format.h>
#include <fmt/ranges.h>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "phantoms/phantoms.hpp"
#include "volume/volume_checks.hpp"

namespace imx {

namespace {

constexpr int kMinSize = 8, kMaxSize = 1024;

struct Named {
  const char* name;
  detail::Phantom (*make)(int size);
};

constexpr Named kPhantoms[] = {
    {"ct-head", detail::ct_head_phantom},     {"cube", detail::cube_phantom},
    {"ellipsoid", detail::ellipsoid_phantom}, {"pet", detail::pet_phantom},
    {"shells", detail::shells_phantom},       {"sphere", detail::sphere_phantom}};

// The phantom `name` at `size`, its voxels not made yet; throws for an unknown name or size.
detail::Phantom find_phantom(const std::string& name, int size) {
  for (const Named& p : kPhantoms) {
    if (name != p.name) continue;
    if (size < kMinSize || size > kMaxSize)
      throw Error(fmt::format("phantom '{}': size {} is out of range [{}, {}]", name, size,
                              kMinSize, kMaxSize));
    return p.make(size);
  }
  throw Error(
      fmt::format("unknown phantom '{}' (available: {})", name, fmt::join(phantom_names(), ", ")));
}

}  // namespace

std::vector<std::string> phantom_names() {
  std::vector<std::string> names;
  for (const Named& p : kPhantoms) names.emplace_back(p.name);
  return names;
}

VolumeData make_phantom(const std::string& name, int size) {
  const detail::Phantom p = find_phantom(name, size);
  return p.sample(VoxelBox::whole(p.header.dims));
}

VolumeHeader phantom_header(const std::string& name, int size) {
  return find_phantom(name, size).header;
}

// Every phantom computes each voxel from its own position, so only the box is computed.
VolumeData make_phantom_region(const std::string& name, int size, const VoxelBox& box) {
  const detail::Phantom p = find_phantom(name, size);
  detail::require_box_inside(p.header.dims, box, fmt::format("phantom '{}'", name));
  return p.sample(box);
}

}  // namespace imx
