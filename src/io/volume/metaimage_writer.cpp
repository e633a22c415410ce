#include <span>
#include <vector>

#include <fmt/format.h>
#include <zlib.h>
#include <glm/geometric.hpp>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/streams/atomic_file.hpp"

namespace imx {

namespace {

const char* met_type_name(VoxelType type) {
  switch (type) {
    case VoxelType::u8:
      return "MET_UCHAR";
    case VoxelType::i16:
      return "MET_SHORT";
    case VoxelType::u16:
      return "MET_USHORT";
    case VoxelType::f32:
      return "MET_FLOAT";
  }
  return "unknown";
}

// MetaImage's CompressedData is a zlib stream (not gzip), and its size goes in the header, so
// the whole volume is compressed in memory first.
std::vector<uint8_t> zlib_compress(std::span<const uint8_t> data, const std::string& what) {
  uLongf size = compressBound(static_cast<uLong>(data.size()));
  std::vector<uint8_t> out(size);
  // Level 6 (zlib's default) keeps phantom files small at a moderate cost in time.
  int rc = compress2(out.data(), &size, data.data(), static_cast<uLong>(data.size()), 6);
  if (rc != Z_OK) throw Error(fmt::format("{}: zlib failed to compress (error {})", what, rc));
  out.resize(size);
  return out;
}

}  // namespace

void write_metaimage(const VolumeData& volume, const std::filesystem::path& file, bool compress) {
  const std::string what = file.string();
  volume.validate(what);
  const glm::dmat4& m = volume.index_to_world;
  // TransformMatrix rows are the unit directions of the index axes; lengths go to spacing.
  glm::dvec3 spacing = volume.spacing();
  std::string matrix, spacing_text;
  for (int a = 0; a < 3; ++a) {
    glm::dvec3 dir = glm::dvec3(m[a]) / spacing[a];
    // {} prints the shortest text that reads back to the same double.
    matrix += fmt::format("{}{} {} {}", a ? " " : "", dir.x, dir.y, dir.z);
    spacing_text += fmt::format("{}{}", a ? " " : "", spacing[a]);
  }
  std::span<const uint8_t> bytes = std::visit(
      [](const auto& v) {
        return std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(v.data()),
                                        v.size() * sizeof(v[0]));
      },
      volume.voxels);
  std::vector<uint8_t> packed;
  if (compress) {
    packed = zlib_compress(bytes, what);
    bytes = packed;
  }
  std::string header = fmt::format(
      "ObjectType = Image\n"
      "NDims = 3\n"
      "BinaryData = True\n"
      "BinaryDataByteOrderMSB = False\n"
      "CompressedData = {}\n"
      "{}"
      "TransformMatrix = {}\n"
      "Offset = {} {} {}\n"
      "CenterOfRotation = 0 0 0\n"
      "ElementSpacing = {}\n"
      "DimSize = {} {} {}\n"
      "ElementType = {}\n"
      "ElementDataFile = LOCAL\n",
      compress ? "True" : "False",
      compress ? fmt::format("CompressedDataSize = {}\n", bytes.size()) : "", matrix, m[3].x,
      m[3].y, m[3].z, spacing_text, volume.dims.x, volume.dims.y, volume.dims.z,
      met_type_name(volume.type()));
  write_file_atomically(file, [&](std::ostream& out) {
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
  });
}

}  // namespace imx
