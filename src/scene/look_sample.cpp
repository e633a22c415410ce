#include "scene/look_sample.hpp"

#include <algorithm>
#include <cstring>
#include <variant>

namespace imx {

namespace {

constexpr size_t kMostSampled = size_t{1} << 26;  // 128 MiB of int16: a look's worth
constexpr int kMostSlices = 16;

}  // namespace

VolumeData look_sample(const VolumeHeader& header,
                       const std::function<VolumeData(const VoxelBox&)>& load_box) {
  const glm::ivec3 n = header.dims;
  // A slice too large for the sample gives a band of rows through its middle.
  const int rows = static_cast<int>(std::min<size_t>(n.y, std::max<size_t>(kMostSampled / n.x, 1)));
  const int first_row = (n.y - rows) / 2;
  const size_t band = static_cast<size_t>(n.x) * rows;
  const int slices = static_cast<int>(
      std::clamp<size_t>(kMostSampled / band, 1, std::min<size_t>(kMostSlices, n.z)));
  VolumeData out;
  out.dims = {n.x, rows, slices};
  out.index_to_world = header.index_to_world;
  bool typed = false;
  for (int s = 0; s < slices; ++s) {
    const int k = static_cast<int>((static_cast<double>(s) + 0.5) * n.z / slices);
    const VolumeData part = load_box({{0, first_row, k}, {n.x, first_row + rows, k + 1}});
    std::visit(
        [&](const auto& from) {
          using Buffer = std::decay_t<decltype(from)>;
          if (!typed) out.voxels = Buffer(std::vector<typename Buffer::value_type>(band * slices));
          typed = true;
          auto& to = std::get<Buffer>(out.voxels);
          std::memcpy(to.mutable_data() + band * s, from.data(),
                      band * sizeof(typename Buffer::value_type));
        },
        part.voxels);
  }
  return out;
}

}  // namespace imx
