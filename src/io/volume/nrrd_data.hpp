// NRRD voxel data: where a header says it is (attached, one or several data files), how it is
// coded, and the read of one frame's box from it.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "intermix/volume.hpp"
#include "io/voxels/raw_voxels.hpp"

namespace imx::detail {

enum class NrrdEncoding : uint8_t { raw, gzip, bzip2, ascii, hex };

// The data of a NRRD file, as its header's 'encoding', 'type', 'endian', 'data file',
// 'line skip' and 'byte skip' describe it.
struct NrrdData {
  std::filesystem::path header;  // the .nrrd or .nhdr file
  NrrdEncoding encoding = NrrdEncoding::raw;
  RawType type = RawType::u8;
  bool big_endian = false;
  // Detached data: the files' names as the header gives them (relative to its folder), in
  // order; each holds an equal share of the elements. Empty: the data follows the header.
  std::vector<std::string> files;
  uint64_t attached_offset = 0;        // where attached data begins in `header`
  long long line_skip = 0;             // lines before the data, in each file
  std::optional<long long> byte_skip;  // bytes before the data in each file; -1: at its end
  uint64_t elements = 0;               // in all files together
  std::string shape;                   // the header's sizes ("4x3x2"), for messages
};

// Where one frame's voxels lie among the data's elements: voxel (i, j, k) of frame f is
// element i * stride[0] + j * stride[1] + k * stride[2] + f * frame_stride. A frame axis that is
// the fastest (Slicer's DWI: 'kinds: list domain domain domain') interleaves the frames:
// stride[0] is then the frame count.
struct NrrdGrid {
  glm::ivec3 dims{0};
  int frames = 1;
  std::array<uint64_t, 3> stride{1, 0, 0};
  uint64_t frame_stride = 0;
};

// The voxels of `box` (inside grid.dims) of frame `frame` (0 <= frame < grid.frames), converted
// and byte-swapped as load_voxels does, holding no more than the box in memory (and 1 MiB).
// Every data file must be there; uncompressed files are checked by their sizes before anything
// is read. Of compressed and text data, each file holding some of the box's voxels is decoded
// to its end, so that its CRC, its length or its count of values is checked whatever part is
// asked for; files holding none are checked by their size only (a bound on what they can hold).
// Throws imx::Error naming the file (and the header) and the fault.
VoxelStorage read_nrrd_voxels(const NrrdData& data, const NrrdGrid& grid, int frame,
                              const VoxelBox& box);

}  // namespace imx::detail
