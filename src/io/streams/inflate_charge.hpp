// What decompressed data an input claims, charged to the memory budget before it is allocated
// or inflated: the accounting half of the one bounded-inflate layer (bounded_inflate.hpp is the
// inflating half). Every container reader that inflates (gzip, zlib, bzip2, zstd, blosc, zip,
// base64-gzip) charges here, so that a file cannot pass the budget one piece at a time.
#pragma once
#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>

namespace imx::detail {

// The memory one reading of one file holds for what it decompressed and decoded: each use of a
// block is charged, so arrays that share one compressed block count once per array, not once in
// all, and what is kept stays charged while temporaries are released.
class InflateCharge {
 public:
  explicit InflateCharge(std::string file) : file_(std::move(file)) {}

  // Adds `bytes` (what `what` claims: "data array 'x' (PointData)") to the charge. Throws
  // imx::OutOfMemory naming the file, the claim, the total and the budget when the total passes
  // the budget, before the caller allocates anything for it.
  void charge(uint64_t bytes, std::string_view what);
  // Takes back `bytes` charged before whose memory has been freed.
  void release(uint64_t bytes) { charged_ -= std::min(bytes, charged_); }
  uint64_t charged() const { return charged_; }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  uint64_t charged_ = 0;
};

// Compressed voxel data (a gzip .nii.gz, .mgz, NRRD gzip or bzip2 data, a compressed MetaImage)
// is read from its start only, so it is never read in bricks: a region of it costs inflating all
// that comes before, once per brick. A frame of it must be one a process can hold whole, as
// require_holdable puts it: at most half the memory budget (`claim`, the bytes a whole read
// keeps) and not `too_many_voxels` (more than one volume in memory holds). Otherwise throws
// imx::OutOfMemory (never VolumeTooLarge, which would send it to bricks) naming the file, the
// claim and the budget, before anything is read.
void refuse_compressed_claim(uint64_t claim, bool too_many_voxels, const std::string& file,
                             std::string_view data);

}  // namespace imx::detail
