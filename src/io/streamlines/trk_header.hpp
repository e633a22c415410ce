// The 1000-byte TrackVis header, read as nibabel 5.0 reads it (streamlines/trk.py).
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/streamlines/trk_space.hpp"

namespace imx::detail {

inline constexpr size_t kTrkHeaderBytes = 1000;

// Values of one name in scalar_name / property_name: columns [first, first + count) of the
// n_scalars (n_properties) stored per point (streamline).
struct TrkValueColumns {
  std::string name;  // UTF-8, blanks trimmed
  int first = 0;
  int count = 0;
  bool packed = false;  // the name declares several values: arrays are "name[i]"
};

struct TrkHeader {
  bool big_endian = false;
  int version = 2;
  TrkSpace space;
  int n_scalars = 0;
  int n_properties = 0;
  std::vector<TrkValueColumns> scalars;     // columns that exist; nibabel's names, in its order
  std::vector<TrkValueColumns> properties;  // likewise
  int32_t n_count = 0;                      // 0: read to the end of the file
};

// Throws imx::Error naming `what` and the field (see trk.hpp); `notes` receives the choices made
// for the user (a vox_to_ras or voxel order that is not recorded, names without values).
TrkHeader parse_trk_header(std::string_view bytes, const std::string& what,
                           std::vector<std::string>& notes);

}  // namespace imx::detail
