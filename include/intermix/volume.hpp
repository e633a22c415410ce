// VolumeData: a 3D grid of scalar voxels in its native type, placed in world space (LPS, mm).
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "intermix/voxel_buffer.hpp"

namespace imx {

enum class VoxelType : uint8_t { u8, i16, u16, f32 };

// A box of voxel indices, lo inclusive, hi exclusive: the part of a volume one process reads
// when a volume is split into bricks (distributed rendering).
struct VoxelBox {
  glm::ivec3 lo{0}, hi{0};

  glm::ivec3 size() const { return hi - lo; }
  bool empty() const { return hi.x <= lo.x || hi.y <= lo.y || hi.z <= lo.z; }
  size_t count() const {
    return empty() ? 0 : static_cast<size_t>(hi.x - lo.x) * (hi.y - lo.y) * (hi.z - lo.z);
  }
  // The whole grid of `dims` voxels.
  static VoxelBox whole(glm::ivec3 dims) { return {glm::ivec3(0), dims}; }
  bool operator==(const VoxelBox&) const = default;
};

const char* voxel_type_name(VoxelType type);

// The voxels in their native type, in VoxelType's order; owned, or a view of external memory
// (VoxelBuffer), so a volume from Python shares a numpy array's memory without a copy.
using VoxelStorage = std::variant<VoxelBuffer<uint8_t>, VoxelBuffer<int16_t>, VoxelBuffer<uint16_t>,
                                  VoxelBuffer<float>>;

// The colours of a colour volume (NIfTI RGB24 / RGBA32, DICOM RGB): per voxel, in the order of
// VolumeData::voxels, its red, green and blue as the file stores them (sRGB-encoded bytes). The
// volume's scalar voxels then hold its luminance (or the file's alpha), so that every scalar path
// (bricks, bounds, statistics, the TF's opacity) serves it unchanged (docs/clinical_data.md).
struct ColourVoxels {
  std::vector<uint8_t> rgb;  // 3 bytes per voxel
};

struct VolumeData {
  glm::ivec3 dims{0};              // voxels along i, j, k; x fastest in memory
  VoxelStorage voxels;             // dims.x * dims.y * dims.z values
  glm::dmat4 index_to_world{1.0};  // voxel centres at integer indices -> world mm (LPS)
  // A colour volume's colours (shown instead of the TF's colour and the planes' grey); null for
  // a scalar volume.
  std::shared_ptr<const ColourVoxels> colours;

  VoxelType type() const { return static_cast<VoxelType>(voxels.index()); }
  size_t voxel_count() const;
  // Length in mm of one index step along each axis (columns of the affine).
  glm::dvec3 spacing() const;
  // The value of one voxel as a double: for tools and tests, not for hot loops.
  double value_at(int i, int j, int k) const;
  // Smallest and largest finite voxel value ({0, 0} when there is none).
  std::pair<double, double> range() const;
  // Throws imx::Error (naming `what`) when dims, storage size or the affine are inconsistent.
  // NaN and inf voxels are valid: no data (non_finite_count).
  void validate(const std::string& what) const;
};

// How many voxels are NaN or infinite (float volumes only; 0 for the others): they are "no data",
// rendered as nothing (transparent, never a maximum, minimum or iso crossing). One scan.
size_t non_finite_count(const VolumeData& volume);

// What distinguishes one frame of a multi-frame (4-D) source from the others: its time point,
// diffusion weighting, echo, cardiac phase or image type. Only what the file says is set.
struct FrameLabel {
  std::optional<double> time_s;   // acquisition time, seconds after the first frame's
  std::optional<double> b_value;  // diffusion weighting, s/mm^2
  // Unit gradient direction along the volume's i, j, k axes (world: the sum of b_vector[a] times
  // index_to_world's unit column a); an FSL .bvec before its x flip. Zero for b = 0.
  std::optional<glm::dvec3> b_vector;
  std::optional<double> echo_time_ms;
  std::optional<double> trigger_time_ms;  // cardiac phase
  std::string image_type;                 // "M", "P", "R", "I" (magnitude, phase, real, imaginary)
  std::string text;                       // the above in words: "t=2 s", "b=1000 (0,0.7,0.7)"
};

// What a volume file holds, without its voxels.
struct VolumeHeader {
  glm::ivec3 dims{0};
  VoxelType type = VoxelType::u8;  // the storage type read_volume gives
  glm::dmat4 index_to_world{1.0};  // as read_volume gives it (LPS)
  // Volumes of this grid in the file: time points, diffusion directions, echoes, components.
  int frames = 1;
  std::vector<FrameLabel> frame_labels;  // one per frame, or empty when the file says nothing
};

// "t=2 s", "b=1000 (0,0.71,0.71)", "TE=12 ms", ...: FrameLabel::text from its fields.
std::string describe_frame(const FrameLabel& label);

// The voxels of `box` (within volume.dims, else imx::Error naming `what`) as a volume of their
// own, placed where they lie: index_to_world is the whole's moved by box.lo.
VolumeData crop(const VolumeData& volume, const VoxelBox& box, const std::string& what);

// index_to_world of the voxels of a box starting at `lo` of a grid placed by `index_to_world`.
glm::dmat4 box_index_to_world(const glm::dmat4& index_to_world, glm::ivec3 lo);

}  // namespace imx
