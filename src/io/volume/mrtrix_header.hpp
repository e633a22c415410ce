// The text header of an MRtrix image (.mif, .mif.gz, .mih), parsed as MRtrix's reader parses it:
// the grid, its placement and scaling, and where and how the values lie on file, for
// mrtrix_reader.cpp to read them.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>

#include "intermix/volume.hpp"
#include "io/voxels/raw_voxels.hpp"

namespace imx::detail {

// Where the values lie: the axes from the fastest-varying on file to the slowest, and which are
// stored from their last index to their first.
struct MrtrixStorage {
  std::array<int64_t, 4> dim{1, 1, 1, 1};  // x, y, z, volumes
  std::array<int, 4> order{0, 1, 2, 3};    // axes, fastest first
  std::array<bool, 4> reversed{false, false, false, false};
  uint64_t offset = 0;  // of the first value, in the (inflated) file
  RawType type = RawType::u8;
  bool swap = false;
  std::filesystem::path file;
  std::string what;
  bool gzipped = false;

  uint64_t count() const { return static_cast<uint64_t>(dim[0] * dim[1] * dim[2] * dim[3]); }
  uint64_t bytes() const { return count() * raw_type_size(type); }
};

// What the header says: the volume it describes, where its values lie, their scaling.
struct MrtrixLayout {
  VolumeHeader header;
  MrtrixStorage data;
  double offset = 0.0, scale = 1.0;
  bool scaled() const { return offset != 0.0 || scale != 1.0; }
};

// The header of `file` (gzipped or not) and the data file it names. Throws imx::Error naming the
// file and the key at fault.
MrtrixLayout read_mrtrix_layout(const std::filesystem::path& file);

}  // namespace imx::detail
