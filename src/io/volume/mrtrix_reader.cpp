// MRtrix's image formats (https://mrtrix.readthedocs.io, "MRtrix image formats"): the values, in
// any axis order, of an image whose header mrtrix_header.cpp parses. Checked against mrconvert
// (MRtrix 3) in the tests.
#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <optional>
#include <span>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/gzip.hpp"
#include "io/streams/inflate_charge.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"
#include "io/volume/mrtrix.hpp"
#include "io/volume/mrtrix_header.hpp"
#include "io/voxels/frame_voxels.hpp"
#include "io/voxels/frames.hpp"
#include "io/voxels/raw_voxels.hpp"
#include "volume/volume_checks.hpp"

namespace imx::detail {

namespace fs = std::filesystem;

namespace {

// The voxels of `box` of volume `frame`, gathered from the stretch of the data that holds them:
// the values are streamed in file order and each one inside the box is copied to its place.
VoxelStorage read_voxels(const MrtrixStorage& s, int frame, const VoxelBox& box) {
  const size_t esize = raw_type_size(s.type);
  const std::array<int64_t, 4> lo{box.lo.x, box.lo.y, box.lo.z, frame};
  const std::array<int64_t, 4> hi{box.hi.x, box.hi.y, box.hi.z, frame + 1};
  // Stride of each axis on file, in values, and the file position of an index.
  std::array<uint64_t, 4> stride{};
  uint64_t step = 1;
  for (int n = 0; n < 4; ++n) {
    stride[s.order[n]] = step;
    step *= static_cast<uint64_t>(s.dim[s.order[n]]);
  }
  auto position = [&](const std::array<int64_t, 4>& idx) {
    uint64_t p = 0;
    for (int a = 0; a < 4; ++a)
      p += stride[a] * static_cast<uint64_t>(s.reversed[a] ? s.dim[a] - 1 - idx[a] : idx[a]);
    return p;
  };
  // The box's first and last values on file lie at two of its corners.
  uint64_t first = UINT64_MAX, last = 0;
  for (int corner = 0; corner < 16; ++corner) {
    std::array<int64_t, 4> idx{};
    for (int a = 0; a < 4; ++a) idx[a] = (corner >> a & 1) ? hi[a] - 1 : lo[a];
    first = std::min(first, position(idx));
    last = std::max(last, position(idx));
  }

  require_regular_file(s.file, s.what);
  std::error_code ec;
  const uintmax_t size = fs::file_size(s.file, ec);
  if (ec) throw Error(fmt::format("{}: cannot read its size: {}", s.what, ec.message()));
  const uint64_t needed = s.offset + s.bytes();
  if (s.gzipped) {
    check_inflatable(static_cast<size_t>(needed), static_cast<size_t>(size), s.what);
    const auto frames = static_cast<uint64_t>(std::max<int64_t>(1, s.dim[3]));
    refuse_compressed_claim(s.bytes() / frames, s.count() / frames > kMaxVoxels, s.what,
                            frames > 1 ? "gzip voxel data of one frame" : "gzip voxel data");
  } else if (size < needed)
    throw Error(
        fmt::format("{}: expected {} bytes of voxel data ({}x{}x{}x{} {}) from byte {}, "
                    "found {} (truncated file?)",
                    s.what, s.bytes(), s.dim[0], s.dim[1], s.dim[2], s.dim[3],
                    raw_type_name(s.type), s.offset, size > s.offset ? size - s.offset : 0));
  std::ifstream in = open_input_stream(s.file, s.what);
  std::optional<GzipStream> gz;
  const uint64_t start = s.offset + first * esize;
  auto short_data = [&] {
    return Error(fmt::format(
        "{}: the data ends before the {} bytes of its {}x{}x{}x{} {} values "
        "(truncated file?)",
        s.what, s.bytes(), s.dim[0], s.dim[1], s.dim[2], s.dim[3], raw_type_name(s.type)));
  };
  if (s.gzipped) {
    gz.emplace(in, s.what);
    if (gz->skip(static_cast<size_t>(start)) < start) throw short_data();
  } else {
    in.seekg(static_cast<std::streamoff>(start));
  }
  auto pull = [&](uint8_t* dst, size_t n) {
    if (gz) {
      if (gz->read(std::span<uint8_t>(dst, n)) < n) throw short_data();
    } else if (!in.read(reinterpret_cast<char*>(dst), static_cast<std::streamsize>(n))) {
      throw short_data();
    }
  };

  const glm::ivec3 out_dims = box.size();
  VoxelStorage voxels =
      load_voxels(s.type, box.count(), s.swap, s.what, [&](std::span<uint8_t> out) {
        // Counters of the value at `first`, along the file's axis order.
        std::array<int64_t, 4> c{};
        uint64_t rest = first;
        for (int n = 0; n < 4; ++n) {
          const int a = s.order[n];
          c[a] = static_cast<int64_t>(rest % static_cast<uint64_t>(s.dim[a]));
          rest /= static_cast<uint64_t>(s.dim[a]);
        }
        std::vector<uint8_t> chunk;
        uint64_t left = last - first + 1;
        while (left > 0) {
          const size_t values =
              static_cast<size_t>(std::min<uint64_t>(left, (size_t{1} << 20) / esize));
          chunk.resize(values * esize);
          pull(chunk.data(), chunk.size());
          left -= values;
          for (size_t v = 0; v < values; ++v) {
            std::array<int64_t, 4> idx;
            bool inside = true;
            for (int a = 0; a < 4; ++a) {
              idx[a] = s.reversed[a] ? s.dim[a] - 1 - c[a] : c[a];
              inside = inside && idx[a] >= lo[a] && idx[a] < hi[a];
            }
            if (inside) {
              const size_t at = (static_cast<size_t>(idx[2] - lo[2]) * out_dims.y +
                                 static_cast<size_t>(idx[1] - lo[1])) *
                                    out_dims.x +
                                static_cast<size_t>(idx[0] - lo[0]);
              std::memcpy(out.data() + at * esize, chunk.data() + v * esize, esize);
            }
            for (int n = 0; n < 4; ++n) {  // the next value on file
              const int a = s.order[n];
              if (++c[a] < s.dim[a]) break;
              c[a] = 0;
            }
          }
        }
      });
  if (gz) {
    // The rest of the stream, so that data short or corrupt anywhere is refused as a whole.
    const uint64_t rest = needed - (start + (last - first + 1) * esize);
    if (gz->skip(static_cast<size_t>(rest)) < rest) throw short_data();
    gz->finish(static_cast<size_t>(needed));
  }
  return voxels;
}

VoxelStorage scaled(VoxelStorage voxels, const MrtrixLayout& l) {
  if (!l.scaled()) return voxels;
  return std::visit(
      [&](const auto& src) -> VoxelStorage {
        std::vector<float> out(src.size());
        for (size_t i = 0; i < src.size(); ++i)
          out[i] = static_cast<float>(l.offset + l.scale * static_cast<double>(src[i]));
        return VoxelBuffer<float>(std::move(out));
      },
      voxels);
}

}  // namespace

VolumeHeader read_mrtrix_header(const fs::path& file) {
  VolumeHeader header = read_mrtrix_layout(file).header;
  check_placement(header.index_to_world, file.string());
  return header;
}

VolumeData read_mrtrix_region(const fs::path& file, const VoxelBox& box, int frame) {
  const MrtrixLayout l = read_mrtrix_layout(file);
  return frame_box_volume(
      l.header, l.header.frames, frame, box, file.string(),
      [&](const VoxelBox& b) { return scaled(read_voxels(l.data, frame, b), l); });
}

VolumeData read_mrtrix(const fs::path& file, int frame) {
  const MrtrixLayout l = read_mrtrix_layout(file);
  return frame_box_volume(
      l.header, l.header.frames, frame, VoxelBox::whole(l.header.dims), file.string(),
      [&](const VoxelBox& b) { return scaled(read_voxels(l.data, frame, b), l); });
}

}  // namespace imx::detail
