#include "io/dicom/dicom_stack.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "intermix/error.hpp"

namespace imx::detail {

namespace {

std::string frame_name(const DicomFrame& f, bool multi) {
  return multi ? fmt::format("{} frame {}", f.file.string(), f.frame + 1) : f.file.string();
}

}  // namespace

DicomStack order_slices(std::vector<DicomFrame> frames, int rows, int columns,
                        std::optional<double> slice_spacing, const std::string& what) {
  DicomStack s;
  s.rows = rows;
  s.columns = columns;
  s.slice_spacing = slice_spacing;
  if (frames.empty()) throw Error(fmt::format("{}: the series has no images", what));
  const bool multi =
      std::any_of(frames.begin(), frames.end(), [](const auto& f) { return f.frame > 0; });
  const DicomFrame& first = frames.front();
  if (first.row_direction && first.column_direction) {
    s.row_direction = *first.row_direction;
    s.column_direction = *first.column_direction;
    glm::dvec3 n = glm::cross(s.row_direction, s.column_direction);
    if (glm::length(n) < 0.5)
      throw Error(
          fmt::format("{}: ImageOrientationPatient (0020,0037) has parallel row and "
                      "column directions",
                      frame_name(first, multi)));
    s.normal = glm::normalize(n);
  } else if (frames.size() > 1) {
    throw Error(
        fmt::format("{}: no ImageOrientationPatient (0020,0037): cannot order the "
                    "slices",
                    frame_name(first, multi)));
  } else {
    s.notes.push_back("no ImageOrientationPatient: axial orientation assumed");
  }
  if (first.pixel_spacing) {
    s.row_spacing = first.pixel_spacing->x;  // PixelSpacing: between rows, then columns
    s.column_spacing = first.pixel_spacing->y;
  } else {
    s.notes.push_back("no PixelSpacing (0028,0030): 1 mm pixels assumed");
  }
  for (const DicomFrame& f : frames) {
    if (frames.size() > 1 && !f.position)
      throw Error(fmt::format("{}: no ImagePositionPatient (0020,0032): cannot order the slices",
                              frame_name(f, multi)));
    // Said as the files say it: a file without the tag has none, not the 1 mm assumed for it.
    auto said = [](const DicomFrame& d) {
      return d.pixel_spacing
                 ? fmt::format("PixelSpacing {}\\{}", d.pixel_spacing->x, d.pixel_spacing->y)
                 : std::string("no PixelSpacing");
    };
    const glm::dvec2 ps = f.pixel_spacing.value_or(glm::dvec2(1.0));
    if (f.pixel_spacing.has_value() != first.pixel_spacing.has_value() ||
        std::abs(ps.x - s.row_spacing) > 1e-4 * s.row_spacing ||
        std::abs(ps.y - s.column_spacing) > 1e-4 * s.column_spacing)
      throw Error(fmt::format("{} has {}, but {} has {}", frame_name(f, multi), said(f),
                              frame_name(first, multi), said(first)));
  }
  if (!frames.front().position) frames.front().position = glm::dvec3(0.0);
  auto along = [&](const DicomFrame& f) { return glm::dot(*f.position, s.normal); };
  std::stable_sort(frames.begin(), frames.end(),
                   [&](const auto& a, const auto& b) { return along(a) < along(b); });
  const size_t n = frames.size();
  std::vector<double> gaps;
  for (size_t i = 0; i + 1 < n; ++i) {
    double gap = along(frames[i + 1]) - along(frames[i]);
    if (gap < kDuplicateMm)
      throw Error(fmt::format(
          "{}: duplicate slice position: {} and {} both lie at {:.3f} mm "
          "along the slice normal{}",
          what, frame_name(frames[i], multi), frame_name(frames[i + 1], multi), along(frames[i]),
          !frames[i].file.empty() && frames[i].file == frames[i + 1].file
              ? ""
              : " (two acquisitions or echoes in one series?)"));
    gaps.push_back(gap);
  }
  // An isolated wide gap is a hole; a run of wide gaps is a change of protocol.
  for (size_t i = 0; i < gaps.size() && gaps.size() >= 2; ++i) {
    double neighbour = std::max(i > 0 ? gaps[i - 1] : 0.0, i + 1 < gaps.size() ? gaps[i + 1] : 0.0);
    if (gaps[i] >= kMissingRatio * neighbour)
      throw Error(
          fmt::format("{}: missing slice: a gap of {:.3f} mm between {} and {}, where the "
                      "neighbouring gaps are {:.3f} mm",
                      what, gaps[i], frame_name(frames[i], multi), frame_name(frames[i + 1], multi),
                      neighbour));
  }
  s.frames = std::move(frames);
  return s;
}

SliceGrid plan_slice_grid(DicomStack& stack, std::optional<double> spacing_mm,
                          const std::string& what) {
  SliceGrid grid;
  const std::vector<DicomFrame>& f = stack.frames;
  const size_t n = f.size();
  const glm::dvec3 p0 = *f.front().position;
  glm::dvec3 step;
  grid.index_to_world[0] = glm::dvec4(stack.row_direction * stack.column_spacing, 0.0);
  grid.index_to_world[1] = glm::dvec4(stack.column_direction * stack.row_spacing, 0.0);
  grid.index_to_world[3] = glm::dvec4(p0, 1.0);
  if (spacing_mm && !(*spacing_mm > 0.0 && std::isfinite(*spacing_mm)))
    throw Error(
        fmt::format("{}: slice_spacing_mm {} must be a positive number", what, *spacing_mm));
  if (n == 1) {
    if (spacing_mm)
      throw Error(fmt::format("{}: slice_spacing_mm needs more than one slice", what));
    grid.index_to_world[2] = glm::dvec4(stack.normal * stack.slice_spacing.value_or(1.0), 0.0);
    grid.blends = {SliceBlend{0, 0.0}};
    return grid;
  }
  const glm::dvec3 span = *f.back().position - p0;
  const double length = glm::length(span);
  step = span / static_cast<double>(n - 1);
  double deviation = 0.0, min_gap = INFINITY, max_gap = 0.0;
  for (size_t s = 0; s < n; ++s) {
    deviation =
        std::max(deviation, glm::length(*f[s].position - (p0 + step * static_cast<double>(s))));
    if (s + 1 < n) {
      double gap = glm::length(*f[s + 1].position - *f[s].position);
      min_gap = std::min(min_gap, gap);
      max_gap = std::max(max_gap, gap);
    }
  }
  const bool even = deviation <= std::max(0.01, 0.01 * glm::length(step));
  if (even && (!spacing_mm || std::abs(*spacing_mm - glm::length(step)) <= 1e-6 * *spacing_mm)) {
    if (deviation > 0.01)
      stack.notes.push_back(
          fmt::format("slice positions deviate up to {:.3f} mm from even "
                      "spacing; placed evenly",
                      deviation));
    grid.index_to_world[2] = glm::dvec4(step, 0.0);
    for (size_t s = 0; s < n; ++s) grid.blends.push_back({static_cast<int>(s), 0.0});
    return grid;
  }
  // Distances along the line through the first and last positions; the rest must lie on it.
  std::vector<double> at(n);
  const glm::dvec3 axis = span / length;
  for (size_t s = 0; s < n; ++s) {
    at[s] = glm::dot(*f[s].position - p0, axis);
    double off = glm::length(*f[s].position - (p0 + axis * at[s]));
    if (off > std::max(0.01, 0.01 * min_gap))
      throw Error(
          fmt::format("{}: slice positions do not lie on one line: {} is {:.3f} mm off "
                      "the line from the first slice to the last",
                      what, f[s].file.string(), off));
  }
  const double wanted = spacing_mm.value_or(min_gap);
  const double intervals = std::ceil(length / wanted - 1e-6);
  if (intervals + 1 > kMaxResampledSlices)
    throw Error(fmt::format("{}: resampling {:.2f} mm at {} mm spacing gives more than {} slices",
                            what, length, wanted, kMaxResampledSlices));
  const int count = static_cast<int>(intervals) + 1;
  const double h = length / intervals;
  grid.index_to_world[2] = glm::dvec4(axis * h, 0.0);
  grid.resampled = true;
  size_t lower = 0;
  for (int k = 0; k < count; ++k) {
    double x = k == count - 1 ? at[n - 1] : k * h;
    while (lower + 2 < n && at[lower + 1] <= x) ++lower;
    double w = (x - at[lower]) / (at[lower + 1] - at[lower]);
    grid.blends.push_back({static_cast<int>(lower), std::clamp(w, 0.0, 1.0)});
  }
  if (even)
    stack.notes.push_back(
        fmt::format("resampled {} slices {:.3f} mm apart to {} slices {:.4g} mm "
                    "apart (slice_spacing_mm)",
                    n, glm::length(step), count, h));
  else
    stack.notes.push_back(
        fmt::format("uneven slice spacing (gaps from {:.3g} to {:.3g} mm): "
                    "resampled to {} slices {:.4g} mm apart, blending "
                    "neighbouring slices linearly",
                    min_gap, max_gap, count, h));
  return grid;
}

}  // namespace imx::detail
