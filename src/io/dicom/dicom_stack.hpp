// The geometry of a series' slices: ordering along the slice normal, the checks for duplicate
// and missing slices, and the even grid the volume is placed on (sheared under gantry tilt,
// resampled when the acquired spacing is uneven).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "io/dicom/dicom_header.hpp"

namespace imx::detail {

inline constexpr double kDuplicateMm = 0.01;  // slices closer than this are the same place
inline constexpr double kMissingRatio = 1.5;  // a gap this much wider than both neighbours
inline constexpr int kMaxResampledSlices = 20000;

struct DicomStack {
  int rows = 0, columns = 0;
  glm::dvec3 row_direction{1, 0, 0}, column_direction{0, 1, 0}, normal{0, 0, 1};
  double column_spacing = 1.0, row_spacing = 1.0;  // mm between columns (along i), rows (j)
  std::optional<double> slice_spacing;             // the tags', for a single slice
  std::vector<DicomFrame> frames;                  // sorted by position along the normal
  std::vector<std::string> notes;
};

// Sorts `frames` (one series: same size and orientation) and checks them. Throws imx::Error
// naming the files for missing positions, mixed pixel spacing, duplicate positions (within
// kDuplicateMm) and missing slices (a gap at least kMissingRatio times each neighbouring gap).
DicomStack order_slices(std::vector<DicomFrame> frames, int rows, int columns,
                        std::optional<double> slice_spacing, const std::string& what);

// Output slice k blends acquired slices `lower` and lower + 1: (1 - weight) * a + weight * b.
struct SliceBlend {
  int lower = 0;
  double weight = 0.0;
};

struct SliceGrid {
  glm::dmat4 index_to_world{1.0};
  std::vector<SliceBlend> blends;  // one per output slice
  bool resampled = false;
};

// The even grid of a stack: the acquired slices themselves when evenly spaced (every position
// within max(0.01 mm, 1% of the step) of the line from the first to the last), else slices
// `spacing_mm` apart (default: the smallest gap), the spacing shortened so that the first and
// last acquired slices lie on the grid. Gaps and spacing are measured along the line through the
// slice positions (the stacking axis, sheared under gantry tilt). Notes go to stack.notes.
SliceGrid plan_slice_grid(DicomStack& stack, std::optional<double> spacing_mm,
                          const std::string& what);

}  // namespace imx::detail
