#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/streams/atomic_file.hpp"
#include "io/streams/gzip.hpp"

namespace imx {

namespace {

// teem's canonical names, which every NRRD reader knows.
const char* nrrd_type_name(VoxelType type) {
  switch (type) {
    case VoxelType::u8:
      return "unsigned char";
    case VoxelType::i16:
      return "short";
    case VoxelType::u16:
      return "unsigned short";
    case VoxelType::f32:
      return "float";
  }
  return "unknown";
}

std::string vector_text(const glm::dvec4& v) {
  // {} prints the shortest text that reads back to the same double.
  return fmt::format("({},{},{})", v.x, v.y, v.z);
}

}  // namespace

void write_nrrd(const VolumeData& volume, const std::filesystem::path& file, bool gzip) {
  volume.validate(file.string());
  const glm::dmat4& m = volume.index_to_world;
  std::string header = fmt::format(
      "NRRD0004\n"
      "# Written by intermix\n"
      "type: {}\n"
      "dimension: 3\n"
      "space: left-posterior-superior\n"
      "sizes: {} {} {}\n"
      "space directions: {} {} {}\n"
      "kinds: domain domain domain\n"
      "endian: little\n"
      "encoding: {}\n"
      "space origin: {}\n\n",
      nrrd_type_name(volume.type()), volume.dims.x, volume.dims.y, volume.dims.z, vector_text(m[0]),
      vector_text(m[1]), vector_text(m[2]), gzip ? "gzip" : "raw", vector_text(m[3]));
  // Raw voxels start at a multiple of 64 bytes (a comment line pads the header), so that
  // readers can map them in place, aligned (mapped_voxels.hpp).
  if (!gzip && header.size() % 64 != 0) {
    header.pop_back();  // the blank line that ends the header comes after the comment
    const size_t pad = (64 - (header.size() + 3) % 64) % 64;
    header += '#';
    header.append(pad, ' ');
    header += "\n\n";
  }
  std::span<const uint8_t> bytes = std::visit(
      [](const auto& v) {
        return std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(v.data()),
                                        v.size() * sizeof(v[0]));
      },
      volume.voxels);
  write_file_atomically(file, [&](std::ostream& out) {
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    // Level 6 (zlib's default) keeps phantom files small at a moderate cost in time.
    if (gzip)
      detail::gzip(bytes, out, 6, file.string());
    else
      out.write(reinterpret_cast<const char*>(bytes.data()),
                static_cast<std::streamsize>(bytes.size()));
  });
}

}  // namespace imx
