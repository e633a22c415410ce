#include "io/streams/inflate_charge.hpp"

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"

namespace imx::detail {

void InflateCharge::charge(uint64_t bytes, std::string_view what) {
  const uint64_t budget = input_limits().max_memory;
  const uint64_t before = charged_;
  // Saturating: a claim near 2^64 must not wrap to a small total.
  charged_ = bytes > UINT64_MAX - before ? UINT64_MAX : before + bytes;
  if (charged_ <= budget) return;
  if (before == 0)
    throw OutOfMemory(
        fmt::format("{}: {} claims {}, more than the memory budget of {} (raise it "
                    "with --max-memory)",
                    file_, what, format_bytes(bytes), format_bytes(budget)));
  throw OutOfMemory(fmt::format(
      "{}: {} claims {}, which with the {} this file claimed before is more than the memory "
      "budget of {} (raise it with --max-memory)",
      file_, what, format_bytes(bytes), format_bytes(before), format_bytes(budget)));
}

void refuse_compressed_claim(uint64_t claim, bool too_many_voxels, const std::string& file,
                             std::string_view data) {
  const uint64_t budget = input_limits().max_memory;
  if (!too_many_voxels && claim <= budget / 2) return;
  throw OutOfMemory(fmt::format(
      "{}: its {} claims {}, more than one volume read whole may take (at most 2^31 voxels and "
      "half the memory budget of {}; raise it with --max-memory). Compressed data cannot be "
      "read in bricks: decompress the file to render it in bricks",
      file, data, format_bytes(claim), format_bytes(budget)));
}

}  // namespace imx::detail
