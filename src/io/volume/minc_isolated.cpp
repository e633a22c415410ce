// read_minc, read_minc_header and read_minc_region: libhdf5 runs in a child process
// (core/isolated_call.hpp), so that a corrupt MINC-2 file that makes it fault or corrupt memory
// ends as one error naming the file, not as the end of the program.
#include <algorithm>
#include <cstring>
#include <functional>
#include <string>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "core/isolated_call.hpp"
#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/volume/minc.hpp"
#include "io/voxels/frames.hpp"

namespace imx::detail {
namespace {

// What a header is in the shared memory: the fixed part, then per frame its time and its text.
struct PackedHeader {
  int32_t dims[3];
  int32_t type;
  double index_to_world[16];
  int32_t frames;
  int32_t labels;
};
constexpr size_t kMaxLabelText = 64;
struct PackedLabel {
  double time_s;
  int32_t has_time;
  char text[kMaxLabelText];
};
// Frames a MINC header may list in the shared memory (a 16 MiB map, touched only as used).
constexpr size_t kMaxPackedLabels =
    ((size_t{16} << 20) - sizeof(PackedHeader)) / sizeof(PackedLabel);

void pack(const VolumeHeader& h, std::span<std::byte> out, const std::string& what) {
  if (h.frame_labels.size() > kMaxPackedLabels)
    throw Error(fmt::format("{}: {} frames; at most {} are read", what, h.frame_labels.size(),
                            kMaxPackedLabels));
  PackedHeader p{};
  for (int a = 0; a < 3; ++a) p.dims[a] = h.dims[a];
  p.type = static_cast<int32_t>(h.type);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) p.index_to_world[c * 4 + r] = h.index_to_world[c][r];
  p.frames = h.frames;
  p.labels = static_cast<int32_t>(h.frame_labels.size());
  std::memcpy(out.data(), &p, sizeof p);
  for (size_t i = 0; i < h.frame_labels.size(); ++i) {
    PackedLabel l{};
    l.has_time = h.frame_labels[i].time_s.has_value();
    l.time_s = h.frame_labels[i].time_s.value_or(0.0);
    std::strncpy(l.text, h.frame_labels[i].text.c_str(), kMaxLabelText - 1);
    std::memcpy(out.data() + sizeof p + i * sizeof l, &l, sizeof l);
  }
}

VolumeHeader unpack(std::span<const std::byte> in) {
  PackedHeader p;
  std::memcpy(&p, in.data(), sizeof p);
  VolumeHeader h;
  h.dims = {p.dims[0], p.dims[1], p.dims[2]};
  h.type = static_cast<VoxelType>(p.type);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) h.index_to_world[c][r] = p.index_to_world[c * 4 + r];
  h.frames = p.frames;
  for (int32_t i = 0; i < p.labels; ++i) {
    PackedLabel l;
    std::memcpy(&l, in.data() + sizeof p + static_cast<size_t>(i) * sizeof l, sizeof l);
    FrameLabel label;
    if (l.has_time) label.time_s = l.time_s;
    label.text = std::string(l.text, strnlen(l.text, kMaxLabelText));
    h.frame_labels.push_back(std::move(label));
  }
  return h;
}

// Runs `work` in a child with `bytes` of shared memory; its failures become one imx::Error.
void run_in_child(const std::filesystem::path& file, size_t bytes,
                  const std::function<void(std::span<std::byte>)>& work,
                  const std::function<void(std::span<const std::byte>)>& finished) {
  constexpr double kSeconds = 600.0;
  const IsolatedResult r = run_isolated(bytes, work, kSeconds, finished, input_limits().max_memory);
  switch (r.end) {
    case IsolatedResult::End::failed:
      throw Error(r.error);
    case IsolatedResult::End::crashed:
      throw Error(fmt::format("{}: libhdf5 failed ({}) reading this file: a corrupt MINC-2 file",
                              file.string(), r.detail));
    case IsolatedResult::End::timed_out:
      throw Error(fmt::format("{}: libhdf5 did not finish reading it in {:.0f} s", file.string(),
                              kSeconds));
    case IsolatedResult::End::over_memory:
      throw Error(fmt::format("{}: libhdf5 needed more than the memory budget of {} reading it",
                              file.string(), format_bytes(input_limits().max_memory)));
    case IsolatedResult::End::finished:
      break;
  }
}

size_t type_size(VoxelType type) {
  return type == VoxelType::u8 ? 1 : type == VoxelType::f32 ? 4 : 2;
}

template <class T>
VoxelStorage storage_from(std::span<const std::byte> in, size_t count) {
  std::vector<T> values(count);
  std::memcpy(values.data(), in.data(), count * sizeof(T));
  return VoxelBuffer<T>(std::move(values));
}

VoxelStorage read_box(const std::filesystem::path& file, const VolumeHeader& header, int frame,
                      const VoxelBox& box) {
  const size_t count = box.count(), bytes = count * type_size(header.type);
  check_memory(2 * bytes, file.string());  // the shared map and the volume
  VoxelStorage out;
  run_in_child(
      file, std::max<size_t>(bytes, 1),
      [&](std::span<std::byte> shared) {
        const VoxelStorage voxels = read_minc_box_in_process(file, frame, box);
        std::visit(
            [&](const auto& buffer) {
              if (buffer.size() * sizeof(*buffer.data()) != bytes)
                throw Error(file.string() + ": the child read another type or size");
              std::memcpy(shared.data(), buffer.data(), bytes);
            },
            voxels);
      },
      [&](std::span<const std::byte> shared) {
        switch (header.type) {
          case VoxelType::u8:
            out = storage_from<uint8_t>(shared, count);
            break;
          case VoxelType::i16:
            out = storage_from<int16_t>(shared, count);
            break;
          case VoxelType::u16:
            out = storage_from<uint16_t>(shared, count);
            break;
          case VoxelType::f32:
            out = storage_from<float>(shared, count);
            break;
        }
      });
  return out;
}

}  // namespace

VolumeHeader read_minc_header(const std::filesystem::path& file) {
  VolumeHeader header;
  run_in_child(
      file, size_t{16} << 20,
      [&](std::span<std::byte> shared) {
        pack(read_minc_header_in_process(file), shared, file.string());
      },
      [&](std::span<const std::byte> shared) { header = unpack(shared); });
  return header;
}

VolumeData read_minc_region(const std::filesystem::path& file, const VoxelBox& box, int frame) {
  const VolumeHeader header = read_minc_header(file);
  return frame_box_volume(header, header.frames, frame, box, file.string(),
                          [&](const VoxelBox& b) { return read_box(file, header, frame, b); });
}

VolumeData read_minc(const std::filesystem::path& file, int frame) {
  const VolumeHeader header = read_minc_header(file);
  return frame_box_volume(header, header.frames, frame, VoxelBox::whole(header.dims), file.string(),
                          [&](const VoxelBox& b) { return read_box(file, header, frame, b); });
}

}  // namespace imx::detail
