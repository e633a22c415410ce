#include "io/streamlines/trk_space.hpp"

#include <cmath>
#include <string_view>

#include <fmt/format.h>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "intermix/error.hpp"
#include "io/streams/header_text.hpp"

namespace imx::detail {
namespace {

// nibabel's orientation arrays: per input axis, the output axis (0 R-L, 1 A-P, 2 S-I) and +1/-1.
struct AxisMap {
  int axis = 0;
  int flip = 1;
};
using Orientation = std::array<AxisMap, 3>;

Orientation voxel_order_orientation(std::string_view order, const std::string& what) {
  auto refuse = [&] {
    return Error(fmt::format(
        "{}: voxel_order '{}' is not three distinct axis letters (one of L/R, P/A and I/S each)",
        what, shown(order)));
  };
  if (order.size() != 3) throw refuse();
  Orientation o;
  bool seen[3] = {false, false, false};
  for (size_t i = 0; i < 3; ++i) {
    const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(order[i])));
    const std::string_view negative = "LPI", positive = "RAS";
    const size_t n = negative.find(c), p = positive.find(c);
    if (n == std::string_view::npos && p == std::string_view::npos) throw refuse();
    o[i].axis = static_cast<int>(n != std::string_view::npos ? n : p);
    o[i].flip = n != std::string_view::npos ? -1 : 1;
    if (seen[o[i].axis]) throw refuse();
    seen[o[i].axis] = true;
  }
  return o;
}

// nibabel's io_orientation: the closest rotation to the column-normalised matrix (its polar
// factor), then each input axis takes the output axis it moves most, used axes removed in turn.
Orientation affine_orientation(const TrkSpace& space, const std::string& what) {
  glm::dmat3 rs(0.0);  // [column][row]
  for (int c = 0; c < 3; ++c) {
    double zoom = 0;
    for (int r = 0; r < 3; ++r) zoom += double(space.vox_to_ras[r][c]) * space.vox_to_ras[r][c];
    zoom = zoom == 0 ? 1 : std::sqrt(zoom);
    for (int r = 0; r < 3; ++r) rs[c][r] = space.vox_to_ras[r][c] / zoom;
  }
  // Unit columns: |det| is 1 for a rotation and 0 when the axes are dependent.
  if (!(std::abs(glm::determinant(rs)) > 1e-6))
    throw Error(fmt::format(
        "{}: vox_to_ras is singular (its voxel axes are not independent); the voxel order "
        "cannot be found from it",
        what));
  glm::dmat3 rotation = rs;
  for (int i = 0; i < 100; ++i) {
    const glm::dmat3 next = 0.5 * (rotation + glm::transpose(glm::inverse(rotation)));
    double change = 0;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) change = std::max(change, std::abs(next[c][r] - rotation[c][r]));
    rotation = next;
    if (change < 1e-15) break;
  }
  Orientation o;
  for (int in = 0; in < 3; ++in) {
    int out = 0;
    for (int r = 1; r < 3; ++r)
      if (std::abs(rotation[in][r]) > std::abs(rotation[in][out])) out = r;
    if (std::abs(rotation[in][out]) <= 1e-8)
      throw Error(fmt::format("{}: vox_to_ras gives no direction for voxel axis {}", what, in));
    o[in] = {out, rotation[in][out] < 0 ? -1 : 1};
    for (int c = 0; c < 3; ++c) rotation[c][out] = 0;
  }
  return o;
}

}  // namespace

glm::dmat4 trk_voxmm_to_ras(const TrkSpace& space, const std::string& what) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(space.voxel_sizes[i]) || space.voxel_sizes[i] == 0)
      throw Error(
          fmt::format("{}: voxel_size {} is {} (points are in voxel sizes: it must be a "
                      "finite nonzero size)",
                      what, "xyz"[i], space.voxel_sizes[i]));
  for (const auto& row : space.vox_to_ras)
    for (float v : row)
      if (!std::isfinite(v))
        throw Error(fmt::format("{}: vox_to_ras holds {}, not a finite number", what, v));

  // glm is column-major: m[column][row].
  glm::dmat4 scale(1.0), half_voxel(1.0), reorder(0.0), vox_to_ras(0.0);
  for (int i = 0; i < 3; ++i) {
    scale[i][i] = 1.0 / double(space.voxel_sizes[i]);
    half_voxel[3][i] = -0.5;
  }
  const Orientation from = voxel_order_orientation(space.voxel_order, what);
  const Orientation to = affine_orientation(space, what);
  // nibabel's ornt_transform(from, to) then inv_ornt_aff(that, dims): header voxel axis i lands
  // on axis `to_in` of the affine's order, flipped about the grid's centre where they differ.
  Orientation transform;
  for (int to_in = 0; to_in < 3; ++to_in)
    for (int from_in = 0; from_in < 3; ++from_in)
      if (from[from_in].axis == to[to_in].axis)
        transform[from_in] = {to_in, from[from_in].flip == to[to_in].flip ? 1 : -1};
  for (int i = 0; i < 3; ++i) {
    // numpy computes (dims - 1) in int16, wrapping as int16 does.
    const double centre = -double(static_cast<int16_t>(space.dims[i] - 1)) / 2.0;
    reorder[transform[i].axis][i] = transform[i].flip;
    reorder[3][i] = transform[i].flip * centre - centre;
  }
  reorder[3][3] = 1;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) vox_to_ras[c][r] = space.vox_to_ras[r][c];

  glm::dmat4 affine = vox_to_ras * reorder * half_voxel * scale;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) {
      affine[c][r] = static_cast<double>(static_cast<float>(affine[c][r]));
      if (!std::isfinite(affine[c][r]))
        throw Error(
            fmt::format("{}: the voxmm to RAS transform overflows float32 (vox_to_ras "
                        "and voxel sizes too far apart)",
                        what));
    }
  return affine;
}

}  // namespace imx::detail
