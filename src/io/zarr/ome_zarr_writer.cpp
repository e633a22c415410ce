#include "io/zarr/ome_zarr_writer.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <vector>

#include <blosc.h>
#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <nlohmann/json.hpp>

#include "intermix/error.hpp"

namespace imx::detail {

namespace {

using Json = nlohmann::json;

const char* dtype_of(VoxelType type) {
  switch (type) {
    case VoxelType::u8:
      return "|u1";
    case VoxelType::i16:
      return "<i2";
    case VoxelType::u16:
      return "<u2";
    case VoxelType::f32:
      return "<f4";
  }
  return "";
}

glm::ivec3 half_of(glm::ivec3 dims) {
  return (dims + 1) / 2;
}

bool axis_aligned(const glm::dmat4& m) {
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if ((r == c) != (m[c][r] != 0.0) || (r == c && m[c][r] < 0.0)) return false;
  return true;
}

void write_text(const std::filesystem::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw Error(fmt::format("{}: cannot write", file.string()));
}

// NGFF's placement of a level: level voxel i covers voxels s*i .. s*i + s - 1 of level 0
// (s = 2^level), so its centre lies at level-0 index s*i + (s - 1)/2, along axes taken as x, y,
// z (NGFF has no orientation; "intermix" keeps an oriented grid's matrix, which the reader
// places each level by through these same numbers).
Json level_transformations(const glm::dmat4& m, int level) {
  const double s = std::ldexp(1.0, level);
  Json scale = Json::array(), translation = Json::array();
  for (int axis = 2; axis >= 0; --axis) {  // z, y, x
    const double spacing = glm::length(glm::dvec3(m[axis]));
    scale.push_back(s * spacing);
    translation.push_back(m[3][axis] + (s - 1.0) / 2.0 * spacing);
  }
  return Json::array({{{"type", "scale"}, {"scale", scale}},
                      {{"type", "translation"}, {"translation", translation}}});
}

void write_metadata(const VolumeHeader& header, const std::filesystem::path& dir, int levels,
                    int chunk, const std::string& name) {
  write_text(dir / ".zgroup", Json{{"zarr_format", 2}}.dump() + "\n");
  Json datasets = Json::array();
  glm::ivec3 dims = header.dims;
  for (int level = 0; level < levels; ++level, dims = half_of(dims)) {
    const std::filesystem::path array = dir / std::to_string(level);
    std::filesystem::create_directory(array);
    const Json zarray = {
        {"zarr_format", 2},
        {"shape", {dims.z, dims.y, dims.x}},
        {"chunks", {chunk, chunk, chunk}},
        {"dtype", dtype_of(header.type)},
        {"compressor",
         {{"id", "blosc"}, {"cname", "lz4"}, {"clevel", 5}, {"shuffle", 1}, {"blocksize", 0}}},
        {"fill_value", 0},
        {"order", "C"},
        {"filters", nullptr},
        {"dimension_separator", "."}};
    write_text(array / ".zarray", zarray.dump(1) + "\n");
    datasets.push_back(
        {{"path", std::to_string(level)},
         {"coordinateTransformations", level_transformations(header.index_to_world, level)}});
  }
  Json axes = Json::array();
  for (const char* axis : {"z", "y", "x"})
    axes.push_back({{"name", axis}, {"type", "space"}, {"unit", "millimeter"}});
  Json attrs = {{"multiscales", Json::array({{{"version", "0.4"},
                                              {"name", name},
                                              {"axes", axes},
                                              {"datasets", datasets},
                                              {"type", "mean"}}})}};
  if (!axis_aligned(header.index_to_world)) {
    Json rows = Json::array();
    for (int r = 0; r < 4; ++r)
      rows.push_back({header.index_to_world[0][r], header.index_to_world[1][r],
                      header.index_to_world[2][r], header.index_to_world[3][r]});
    attrs["intermix"] = {{"index_to_world", rows}};
  }
  write_text(dir / ".zattrs", attrs.dump(1) + "\n");
}

// One level: its slices gather into a slab of one chunk's depth, written chunk by chunk; each
// pair of slices, averaged 2x2x2, is the next level's slice.
template <class T>
class LevelWriter {
 public:
  LevelWriter(std::filesystem::path dir, glm::ivec3 dims, int chunk, LevelWriter* next)
      : dir_(std::move(dir)), dims_(dims), chunk_(chunk), next_(next) {
    slab_.resize(static_cast<size_t>(chunk) * slice_size());
    if (next_) pending_.resize(slice_size());
  }

  size_t slice_size() const { return static_cast<size_t>(dims_.x) * dims_.y; }

  void add(const T* slice) {
    std::copy(slice, slice + slice_size(),
              slab_.data() + static_cast<size_t>(in_slab_) * slice_size());
    if (++in_slab_ == chunk_) flush();
    if (!next_) return;
    if (!has_pending_) {
      std::copy(slice, slice + slice_size(), pending_.data());
      has_pending_ = true;
    } else {
      next_->add(halved(pending_.data(), slice).data());
      has_pending_ = false;
    }
  }

  void finish() {
    if (in_slab_ > 0) flush();
    if (next_) {
      if (has_pending_) next_->add(halved(pending_.data(), pending_.data()).data());
      has_pending_ = false;
      next_->finish();
    }
  }

 private:
  // The next level's slice from two of this level's: means of 2x2x2 voxels, the last row,
  // column or slice of an odd axis repeated (the mean of the voxels there are).
  std::vector<T> halved(const T* a, const T* b) const {
    const glm::ivec3 h = half_of(dims_);
    std::vector<T> out(static_cast<size_t>(h.x) * h.y);
    tbb::parallel_for(0, h.y, [&](int y) {
      const size_t y0 = static_cast<size_t>(2 * y) * dims_.x;
      const size_t y1 = static_cast<size_t>(std::min(2 * y + 1, dims_.y - 1)) * dims_.x;
      for (int x = 0; x < h.x; ++x) {
        const size_t x0 = 2 * static_cast<size_t>(x);
        const size_t x1 = static_cast<size_t>(std::min(2 * x + 1, dims_.x - 1));
        const double sum = double(a[y0 + x0]) + a[y0 + x1] + a[y1 + x0] + a[y1 + x1] + b[y0 + x0] +
                           b[y0 + x1] + b[y1 + x0] + b[y1 + x1];
        if constexpr (std::is_floating_point_v<T>)
          out[static_cast<size_t>(y) * h.x + x] = static_cast<T>(sum / 8.0);
        else
          out[static_cast<size_t>(y) * h.x + x] = static_cast<T>(std::lround(sum / 8.0));
      }
    });
    return out;
  }

  // The slab's chunks, each stored full-size (zarr's edge chunks too), blosc-compressed.
  void flush() {
    const int cz = z0_ / chunk_;
    const int cy_count = (dims_.y + chunk_ - 1) / chunk_,
              cx_count = (dims_.x + chunk_ - 1) / chunk_;
    const size_t c = static_cast<size_t>(chunk_);
    tbb::parallel_for(0, cy_count * cx_count, [&](int index) {
      const int cy = index / cx_count, cx = index % cx_count;
      std::vector<T> block(c * c * c, T(0));
      const int rows = std::min(chunk_, dims_.y - cy * chunk_);
      const int cols = std::min(chunk_, dims_.x - cx * chunk_);
      for (int z = 0; z < in_slab_; ++z)
        for (int y = 0; y < rows; ++y) {
          const T* from = slab_.data() + static_cast<size_t>(z) * slice_size() +
                          static_cast<size_t>(cy * chunk_ + y) * dims_.x + cx * chunk_;
          std::copy(from, from + cols, block.data() + (z * c + y) * c);
        }
      const size_t bytes = block.size() * sizeof(T);
      std::vector<char> packed(bytes + BLOSC_MAX_OVERHEAD);
      const int size = blosc_compress_ctx(5, BLOSC_SHUFFLE, sizeof(T), bytes, block.data(),
                                          packed.data(), packed.size(), "lz4", 0, 1);
      const std::filesystem::path file = dir_ / fmt::format("{}.{}.{}", cz, cy, cx);
      if (size <= 0)
        throw Error(fmt::format("{}: blosc could not compress the chunk", file.string()));
      std::ofstream out(file, std::ios::binary);
      out.write(packed.data(), size);
      out.close();
      if (!out) throw Error(fmt::format("{}: cannot write", file.string()));
    });
    z0_ += in_slab_;
    in_slab_ = 0;
  }

  std::filesystem::path dir_;
  glm::ivec3 dims_;
  int chunk_;
  LevelWriter* next_;
  std::vector<T> slab_, pending_;
  int in_slab_ = 0, z0_ = 0;
  bool has_pending_ = false;
};

template <class T>
void write_levels(const VolumeHeader& header,
                  const std::function<VolumeData(const VoxelBox&)>& read_box,
                  const std::filesystem::path& dir, int levels,
                  const OmeZarrWriteOptions& options) {
  std::vector<std::unique_ptr<LevelWriter<T>>> writers(static_cast<size_t>(levels));
  std::vector<glm::ivec3> dims(static_cast<size_t>(levels), header.dims);
  for (int level = 1; level < levels; ++level) dims[level] = half_of(dims[level - 1]);
  for (int level = levels - 1; level >= 0; --level)
    writers[level] =
        std::make_unique<LevelWriter<T>>(dir / std::to_string(level), dims[level], options.chunk,
                                         level + 1 < levels ? writers[level + 1].get() : nullptr);
  const glm::ivec3 n = header.dims;
  for (int z0 = 0; z0 < n.z; z0 += options.chunk) {
    const int z1 = std::min(z0 + options.chunk, n.z);
    const VolumeData slab = read_box({{0, 0, z0}, {n.x, n.y, z1}});
    const auto* voxels = std::get_if<VoxelBuffer<T>>(&slab.voxels);
    if (!voxels || slab.dims != glm::ivec3(n.x, n.y, z1 - z0))
      throw Error(fmt::format("{}: slices {} to {} were not read as the header said", dir.string(),
                              z0, z1 - 1));
    for (int z = 0; z < z1 - z0; ++z)
      writers[0]->add(voxels->data() + static_cast<size_t>(z) * n.x * n.y);
    if (options.progress) options.progress(static_cast<double>(z1) / n.z);
  }
  writers[0]->finish();
}

}  // namespace

int ome_zarr_level_count(glm::ivec3 dims, int chunk) {
  int levels = 1;
  for (; std::max({dims.x, dims.y, dims.z}) > chunk; ++levels) dims = half_of(dims);
  return levels;
}

void write_ome_zarr(const VolumeHeader& header,
                    const std::function<VolumeData(const VoxelBox&)>& read_box,
                    const std::filesystem::path& dir, const OmeZarrWriteOptions& options) {
  std::error_code ec;
  if (std::filesystem::exists(dir, ec))
    throw Error(fmt::format("{}: exists; remove it or name another folder", dir.string()));
  if (options.chunk < 8 || options.chunk > 512)
    throw Error(fmt::format("{}: chunk edge {} is outside 8 to 512", dir.string(), options.chunk));
  const std::filesystem::path temporary = dir.string() + fmt::format(".tmp-{}", getpid());
  std::filesystem::remove_all(temporary, ec);
  if (!std::filesystem::create_directories(temporary, ec) || ec)
    throw FileError(fmt::format("{}: cannot create the folder: {}", temporary.string(),
                                ec ? ec.message() : "it exists"),
                    ec.value());
  try {
    const int levels = ome_zarr_level_count(header.dims, options.chunk);
    write_metadata(header, temporary, levels, options.chunk, dir.stem().string());
    switch (header.type) {
      case VoxelType::u8:
        write_levels<uint8_t>(header, read_box, temporary, levels, options);
        break;
      case VoxelType::i16:
        write_levels<int16_t>(header, read_box, temporary, levels, options);
        break;
      case VoxelType::u16:
        write_levels<uint16_t>(header, read_box, temporary, levels, options);
        break;
      case VoxelType::f32:
        write_levels<float>(header, read_box, temporary, levels, options);
        break;
    }
    std::filesystem::rename(temporary, dir);
  } catch (...) {
    std::filesystem::remove_all(temporary, ec);
    throw;
  }
}

}  // namespace imx::detail
