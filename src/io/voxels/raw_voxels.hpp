// Raw voxel decoding shared by the volume readers: file element types to VolumeData storage.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <istream>
#include <span>
#include <string>

#include "intermix/volume.hpp"

namespace imx::detail {

// Element types found in volume files. The renderer stores u8, i16, u16 and f32; the others
// convert to the nearest of those (see storage_type_for).
enum class RawType : uint8_t { i8, u8, i16, u16, i32, u32, i64, u64, f32, f64 };

size_t raw_type_size(RawType type);
const char* raw_type_name(RawType type);
// i8 widens to i16 (exact); 32/64-bit integers and doubles narrow to f32 (float keeps every
// value within range, with 24-bit precision, which is enough for rendering).
VoxelType storage_type_for(RawType type);

// The most voxels one volume in memory holds (the kernels address a grid with 32-bit lanes),
// and what a file may declare where its grid is only read whole.
inline constexpr size_t kMaxVoxels = size_t{1} << 31;
// The most voxels a grid read in regions may declare (NRRD, NIfTI, MetaImage, OME-Zarr): grids
// past kMaxVoxels are rendered in bricks (docs/big_data.md); larger headers are corrupt.
inline constexpr size_t kMaxGridVoxels = size_t{1} << 40;

// Throws imx::VolumeTooLarge naming `what` when `box` holds more than one volume in memory may.
void require_loadable_box(const VoxelBox& box, const std::string& what);
// Throws imx::VolumeTooLarge naming `what` unless a process can hold the grid `header` describes
// whole: at most kMaxVoxels voxels, and at most half the memory budget in its storage type.
void require_holdable(const VolumeHeader& header, const std::string& what);

// Voxel storage for `count` elements of `type` in the file. `fill` must write exactly the
// bytes it is given (count * raw_type_size), in file order, or throw. When the file type is
// the storage type the bytes land straight in the result, so no second copy is made.
// `swap_bytes` reverses every element's bytes (big-endian data on this little-endian host).
// Checks the memory budget first (check_memory), naming `what`.
VoxelStorage load_voxels(RawType type, size_t count, bool swap_bytes, const std::string& what,
                         const std::function<void(std::span<uint8_t>)>& fill);

// Where the voxels of `box` lie in the data of a grid of `dims` (x fastest) with elements of
// `element_size` bytes: calls `run(offset, bytes)` for each stretch of contiguous bytes, in file
// order, which is also the box's order. Rows that follow each other in the file make one run,
// so a box spanning whole rows or slices is read in one go.
void for_each_box_run(glm::ivec3 dims, const VoxelBox& box, size_t element_size,
                      const std::function<void(uint64_t offset, size_t bytes)>& run);

// load_voxels for the voxels of `box` (inside `dims`) only: the memory check, the conversion
// and the byte swapping apply to the box alone. `fill(offset, bytes)` must write the bytes
// found `offset` bytes into the voxel data, or throw; its calls are for_each_box_run's runs.
VoxelStorage load_voxels_region(RawType type, glm::ivec3 dims, const VoxelBox& box, bool swap_bytes,
                                const std::string& what,
                                const std::function<void(uint64_t, std::span<uint8_t>)>& fill);

// load_voxels_region from uncompressed data starting at byte `start` of `in`, seeking to each
// run. The caller has checked that the file holds the whole grid's data; a file that shrinks
// meanwhile still gives an imx::Error naming `what`.
VoxelStorage load_raw_voxels(std::istream& in, uint64_t start, RawType type, glm::ivec3 dims,
                             const VoxelBox& box, bool swap_bytes, const std::string& what);

// load_voxels_region from gzip (or zlib) data at `in`'s position, after dropping `skip` inflated
// bytes. The stream is inflated to its end, dropping what lies outside the box, so that data
// that is short or corrupt anywhere is refused as a whole read refuses it. Throws imx::Error
// naming `what` when the data is corrupt or ends early.
VoxelStorage load_gzip_voxels(std::istream& in, size_t skip, RawType type, glm::ivec3 dims,
                              const VoxelBox& box, bool swap_bytes, const std::string& what);

}  // namespace imx::detail
