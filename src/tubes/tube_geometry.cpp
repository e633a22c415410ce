#include "tubes/tube_geometry.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "tubes/connectome_primitives.hpp"
#include "tubes/tube_selection.hpp"

namespace imx {

TubeGeometry::TubeGeometry(const StreamlineObject& object, float pad)
    : streamlines_(object.streamlines),
      radius_(static_cast<float>(object.radius)),
      pad_(object.connectome ? 0.0f : std::max(pad, 0.0f)) {
  if (object.connectome) {
    build_connectome(object);
    return;
  }
  if (!streamlines_) throw Error(fmt::format("streamlines '{}': has no streamlines", object.name));
  const Streamlines& s = *streamlines_;
  const std::vector<uint32_t> selected = select_streamlines(object);
  selected_count_ = selected.size();
  size_t segments = 0;
  for (uint32_t i : selected) segments += s.length(i) - 1;
  check_memory(tube_bytes(selected.size(), segments),
               fmt::format("streamlines '{}' ({} segments)", object.name, segments));
  if (segments + TubeBvh::kRunExtra * (segments / TubeBvh::kRunSegments + selected.size()) >=
      TubeBvh::kMaxStream)
    throw Error(
        fmt::format("streamlines '{}': {} segments are more than one object's tubes hold "
                    "(about {} million); draw a stride of them (\"stride\")",
                    object.name, segments, TubeBvh::kMaxStream * 2 / 3 / 1000000));
  segment_points_.reserve(segments);
  for (uint32_t i : selected)
    for (uint32_t p = s.offsets[i]; p + 1 < s.offsets[i + 1]; ++p) segment_points_.push_back(p);
  bvh_ = TubeBvh({s.points, segment_points_, radius_ + pad_, {}});
  bytes_ = segment_points_.capacity() * sizeof(uint32_t) + bvh_.bytes();
}

// A tube is a capsule between its two ends, of its own radius; a sphere a capsule of no length.
void TubeGeometry::build_connectome(const StreamlineObject& object) {
  connectome_ = true;
  const ConnectomePrimitives shown =
      connectome_primitives(*object.connectome, object.connectome_look);
  const size_t primitives = shown.tubes.size() + shown.spheres.size();
  check_memory(primitives * (2 * 12 + 4 + 4 + 12 + 2 * 40),
               fmt::format("connectome '{}' ({} tubes, {} spheres)", object.name,
                           shown.tubes.size(), shown.spheres.size()));
  primitive_points_.reserve(2 * primitives);
  primitive_radii_.reserve(primitives);
  primitive_colors_.reserve(primitives);
  auto add = [&](const glm::vec3& a, const glm::vec3& b, float radius, const glm::vec3& color) {
    segment_points_.push_back(static_cast<uint32_t>(primitive_points_.size()));
    primitive_points_.push_back(a);
    primitive_points_.push_back(b);
    primitive_radii_.push_back(radius);
    primitive_colors_.push_back(color);
  };
  for (const ConnectomeTube& t : shown.tubes) add(t.a, t.b, t.radius, t.color);
  for (const ConnectomeSphere& s : shown.spheres) add(s.center, s.center, s.radius, s.color);
  bvh_ = TubeBvh({primitive_points_, segment_points_, 0.0f, primitive_radii_});
  bytes_ = bvh_.bytes() + primitives * (2 * sizeof(glm::vec3) + sizeof(float) + sizeof(uint32_t) +
                                        sizeof(glm::vec3));
}

TubeGeometry::~TubeGeometry() = default;

uint32_t TubeGeometry::streamline(uint32_t segment) const {
  const std::vector<uint32_t>& offsets = streamlines_->offsets;
  const uint32_t point = segment_points_[segment];
  return static_cast<uint32_t>(std::upper_bound(offsets.begin(), offsets.end(), point) -
                               offsets.begin() - 1);
}

}  // namespace imx
