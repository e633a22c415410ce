#include "io/voxels/mapped_voxels.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <memory>

#include "intermix/error.hpp"
#include "io/streams/input_file.hpp"

namespace imx::detail {
namespace {

template <class T>
std::optional<VoxelStorage> map_as(const std::filesystem::path& path, uint64_t offset,
                                   uint64_t count) {
  if (offset % alignof(T) != 0 || count == 0) return std::nullopt;
  InputFd file;
  try {
    file = open_input(path);
  } catch (const Error&) {
    return std::nullopt;  // the caller reads the file the usual way, and says what is wrong
  }
  const uint64_t size = file.size();
  const uint64_t bytes = count * sizeof(T);
  if (bytes / sizeof(T) != count || offset > size || size - offset < bytes) return std::nullopt;
  const int fd = file.release();
  const auto page = static_cast<uint64_t>(::sysconf(_SC_PAGESIZE));
  const uint64_t start = offset / page * page, length = offset - start + bytes;
  void* mapped = ::mmap(nullptr, length, PROT_READ, MAP_PRIVATE, fd, static_cast<off_t>(start));
  ::close(fd);  // the mapping keeps the file
  if (mapped == MAP_FAILED) return std::nullopt;
  ::madvise(mapped, length, MADV_WILLNEED);  // read ahead while the caller sets up
  std::shared_ptr<const void> owner(
      mapped, [length](const void* p) { ::munmap(const_cast<void*>(p), length); });
  const T* data = reinterpret_cast<const T*>(static_cast<const char*>(mapped) + (offset - start));
  return VoxelStorage(VoxelBuffer<T>::view(data, count, std::move(owner)));
}

}  // namespace

std::optional<VoxelStorage> map_voxels(const std::filesystem::path& path, uint64_t offset,
                                       RawType type, uint64_t count) {
  switch (type) {
    case RawType::u8:
      return map_as<uint8_t>(path, offset, count);
    case RawType::i16:
      return map_as<int16_t>(path, offset, count);
    case RawType::u16:
      return map_as<uint16_t>(path, offset, count);
    case RawType::f32:
      return map_as<float>(path, offset, count);
    default:
      return std::nullopt;  // stored converted: read and convert
  }
}

}  // namespace imx::detail
