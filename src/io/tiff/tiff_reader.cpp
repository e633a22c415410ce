#include "io/tiff/tiff_reader.hpp"

#include <cstring>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/tiff/tiff_layout.hpp"
#include "io/voxels/frames.hpp"

namespace imx::detail {

namespace {

void require_channel(int channel, const TiffLayout& l) {
  if (channel < 0 || channel >= l.channels)
    throw Error(fmt::format("{}: channel {} requested, the image has {} (0 to {})", l.what, channel,
                            l.channels, l.channels - 1));
}

// The page a plane names, with its file open in `file` (a folder stack opens one per slice).
const TiffPage& open_plane(const TiffLayout& l, const TiffPlane& plane,
                           std::shared_ptr<TiffFile>& file, int& open_index) {
  if (open_index != plane.file) {
    file = plane.file == 0 ? l.opened : std::make_shared<TiffFile>(l.files[plane.file]);
    open_index = plane.file;
  }
  if (!l.folder) return file->pages()[plane.directory];
  const TiffPage* full = nullptr;
  int count = 0;
  for (const TiffPage& p : file->pages())
    if (!p.reduced && count++ == 0) full = &p;
  if (count != 1)
    throw Error(
        fmt::format("{}: {} pages: a folder stack takes one page per file", file->what(), count));
  check_slice_page(l, *full, file->what());
  return *full;
}

// The voxels of `box` of one channel and time point, slice by slice.
VoxelStorage read_box(const TiffLayout& l, const VoxelBox& box, int frame, int channel) {
  require_loadable_box(box, l.what);
  const size_t element = raw_type_size(l.type);
  const auto rows = static_cast<uint32_t>(box.size().y);
  const size_t width = static_cast<size_t>(box.size().x) * element;
  const size_t row_bytes = static_cast<size_t>(l.dims.x) * element;
  const bool whole_rows = box.lo.x == 0 && box.hi.x == l.dims.x;
  std::shared_ptr<TiffFile> file;
  int open_index = -1;
  return load_voxels(l.type, box.count(), false, l.what, [&](std::span<uint8_t> out) {
    std::vector<uint8_t> band(whole_rows ? 0 : rows * row_bytes);
    size_t at = 0;
    for (int z = box.lo.z; z < box.hi.z; ++z) {
      const TiffPage& page = open_plane(l, l.plane(z, channel, frame), file, open_index);
      const auto y0 = static_cast<uint32_t>(box.lo.y);
      if (whole_rows) {
        file->read_rows(page, y0, y0 + rows, out.subspan(at, rows * row_bytes));
        at += rows * row_bytes;
        continue;
      }
      file->read_rows(page, y0, y0 + rows, band);
      for (uint32_t y = 0; y < rows; ++y, at += width)
        std::memcpy(out.data() + at, band.data() + y * row_bytes + box.lo.x * element, width);
    }
  });
}

VolumeHeader header_of(const TiffLayout& l) {
  VolumeHeader h;
  h.dims = l.dims;
  h.type = storage_type_for(l.type);
  h.index_to_world = l.index_to_world();
  h.frames = l.frames;
  return h;
}

}  // namespace

VolumeHeader read_tiff_header(const std::filesystem::path& path) {
  return header_of(tiff_layout(path));
}

VolumeData read_tiff_region(const std::filesystem::path& path, const VoxelBox& box, int frame,
                            int channel) {
  const TiffLayout l = tiff_layout(path);
  require_channel(channel, l);
  return frame_box_volume(header_of(l), l.frames, frame, box, l.what,
                          [&](const VoxelBox& b) { return read_box(l, b, frame, channel); });
}

VolumeData read_tiff(const std::filesystem::path& path, int frame, int channel) {
  const TiffLayout l = tiff_layout(path);
  require_channel(channel, l);
  return frame_box_volume(header_of(l), l.frames, frame, VoxelBox::whole(l.dims), l.what,
                          [&](const VoxelBox& b) { return read_box(l, b, frame, channel); });
}

}  // namespace imx::detail
