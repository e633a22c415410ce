// Shared pieces of the libFuzzer harnesses: a per-process scratch folder for readers that take a
// file path, and input splitting.
#pragma once
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <variant>

#include <tbb/global_control.h>

#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "intermix/mesh.hpp"
#include "intermix/volume.hpp"

namespace imx::fuzz {

// A memory budget well below libFuzzer's -malloc_limit_mb (2048): an input that asks for more must
// be refused by intermix's own check (--max-memory's), never reach the allocator.
inline const bool kBudgetSet = (set_input_limits({uint64_t{768} << 20, false}), true);

// One worker thread: the readers' parallel loops (TBB) then take the same path on every run, so a
// fuzz run with a fixed seed and input count explores the same way twice (scripts/fuzz --ci).
inline const tbb::global_control kOneThread(tbb::global_control::max_allowed_parallelism, 1);

// The folder the harness writes its inputs to: $IMX_FUZZ_TMP, else /dev/shm (no disk writes),
// else $TMPDIR, else /tmp; one subfolder per process, removed at exit.
class ScratchDir {
 public:
  ScratchDir() {
    namespace fs = std::filesystem;
    fs::path base;
    if (const char* env = std::getenv("IMX_FUZZ_TMP"); env != nullptr && *env != '\0')
      base = env;
    else if (::access("/dev/shm", W_OK) == 0)
      base = "/dev/shm";
    else if (const char* tmp = std::getenv("TMPDIR"); tmp != nullptr && *tmp != '\0')
      base = tmp;
    else
      base = "/tmp";
    remove_stale(base);
    // $IMX_FUZZ_DIR: this exact folder (scripts/fuzz --ci, one process per target), so that
    // paths in messages, and the code that formats them, do not change with the process id.
    if (const char* fixed = std::getenv("IMX_FUZZ_DIR"); fixed != nullptr && *fixed != '\0')
      dir_ = fixed;
    else
      dir_ = base / ("imx-fuzz-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  // Empties the folder, so that nothing a previous input wrote can be read by this one.
  void clear() const {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir_, ec))
      std::filesystem::remove_all(entry.path(), ec);
  }

  // Writes `size` bytes to `name` inside the folder and returns its path.
  std::filesystem::path write(const std::string& name, const void* data, size_t size) const {
    std::filesystem::path p = dir_ / name;
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    if (size > 0) out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.close();
    if (!out) {  // the harness itself is broken: a full /dev/shm, say
      std::fprintf(stderr, "fuzz: cannot write %s: %s\n", p.c_str(), std::strerror(errno));
      std::abort();
    }
    return p;
  }
  std::filesystem::path write(const std::string& name, std::string_view data) const {
    return write(name, data.data(), data.size());
  }

  const std::filesystem::path& path() const { return dir_; }

 private:
  // Removes the folders of harness processes that are gone (a crash skips the destructor).
  static void remove_stale(const std::filesystem::path& base) {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(base, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("imx-fuzz-", 0) != 0) continue;
      char* end = nullptr;
      const long pid = std::strtol(name.c_str() + 9, &end, 10);
      if (pid <= 0 || *end != '\0') continue;
      if (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH)
        std::filesystem::remove_all(entry.path(), ec);
    }
  }

  std::filesystem::path dir_;
};

inline ScratchDir& scratch() {
  static ScratchDir dir;
  return dir;
}

// Splits `input` at the first `marker`: {before, after, true}, or {input, "", false}.
struct Split {
  std::string_view head, tail;
  bool found = false;
};
inline Split split_at(std::string_view input, std::string_view marker) {
  size_t at = input.find(marker);
  if (at == std::string_view::npos) return {input, {}, false};
  return {input.substr(0, at), input.substr(at + marker.size()), true};
}

// With IMX_FUZZ_VERBOSE set, prints why an input was refused (to check that seeds load).
inline void refused(const std::exception& e) {
  static const bool verbose = std::getenv("IMX_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "refused: %s\n", e.what());
}
inline void accepted(const char* what) {
  static const bool verbose = std::getenv("IMX_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "accepted: %s\n", what);
}

// A volume a reader returned must hold as many voxels as its dimensions say (every later stage
// indexes by them); the rest of VolumeData::validate is left to the scene loader.
inline void check_volume(const VolumeData& v) {
  const size_t stored = std::visit([](const auto& s) { return s.size(); }, v.voxels);
  if (v.dims.x <= 0 || v.dims.y <= 0 || v.dims.z <= 0 || stored != v.voxel_count()) {
    std::fprintf(stderr, "fuzz: the reader returned %dx%dx%d dimensions with %zu voxels\n",
                 v.dims.x, v.dims.y, v.dims.z, stored);
    __builtin_trap();
  }
}

// A mesh a reader returned must index only its own vertices, with no normals or colours but
// one per vertex: the renderer indexes by them.
inline void check_mesh(const Mesh& m) {
  if (!m.normals.empty() && m.normals.size() != m.positions.size()) __builtin_trap();
  if (!m.colors.empty() && m.colors.size() != m.positions.size()) __builtin_trap();
  for (const auto& t : m.triangles)
    if (t.x >= m.positions.size() || t.y >= m.positions.size() || t.z >= m.positions.size())
      __builtin_trap();
}

inline std::string_view as_view(const uint8_t* data, size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Detached-header volumes (NRRD .nhdr, MetaImage .mhd): the input is the header, this marker
// line, then the bytes of the data file, which the harness writes as "data.raw" beside it.
inline constexpr std::string_view kDataMarker = "\n@@DATA@@\n";

// The header and region paths of a volume reader on `file`: the header, then a box chosen by
// `pick` (a byte of the input) from the header's dims (its middle half, the whole, the last
// voxel), so that hostile headers reach the seeking and skipping code as well as the whole read.
template <class ReadHeader, class ReadRegion>
void fuzz_region(const std::filesystem::path& file, uint8_t pick, ReadHeader read_header,
                 ReadRegion read_region) {
  try {
    const VolumeHeader h = read_header(file);
    const glm::ivec3 d = h.dims;
    VoxelBox box{d / 4, d / 4 + glm::max(d / 2, glm::ivec3(1))};
    if (pick % 3 == 1) box = VoxelBox::whole(d);
    if (pick % 3 == 2) box = {d - 1, d};
    const VolumeData v = read_region(file, box);
    check_volume(v);
    if (v.dims != box.size() || v.type() != h.type) {
      std::fprintf(stderr, "fuzz: the region read returned %dx%dx%d voxels for a %dx%dx%d box\n",
                   v.dims.x, v.dims.y, v.dims.z, box.size().x, box.size().y, box.size().z);
      __builtin_trap();
    }
    accepted("region");
  } catch (const std::exception& e) {
    refused(e);
  }
}

// `file` through the format registry, as a user's file is read: its header, its last frame (so
// that the skips past the others are reached), then a region of that frame (fuzz_region, `pick`).
inline void fuzz_volume_file(const std::filesystem::path& file, uint8_t pick) {
  int frame = 0;
  try {
    frame = read_volume_header(file).frames - 1;
  } catch (const std::exception& e) {
    refused(e);
  }
  try {
    check_volume(read_volume(file, frame));
    accepted("volume");
  } catch (const std::exception& e) {
    refused(e);
  }
  fuzz_region(
      file, pick, [](const auto& f) { return read_volume_header(f); },
      [frame](const auto& f, const VoxelBox& box) { return read_volume_region(f, box, frame); });
}

// One input through a volume reader: written as `attached`, or, when it holds kDataMarker, split
// into a detached header `detached` and its data file "data.raw" beside it. Only the reader
// runs: validate() and range() would double the time of large volumes. Then the same file
// through the reader's header and region paths (fuzz_region).
template <class Reader, class ReadHeader, class ReadRegion>
int fuzz_volume_reader(const uint8_t* data, size_t size, const char* attached, const char* detached,
                       Reader read, ReadHeader read_header, ReadRegion read_region) {
  const ScratchDir& dir = scratch();
  dir.clear();
  Split parts = split_at(as_view(data, size), kDataMarker);
  std::filesystem::path file;
  if (parts.found) {
    file = dir.write(detached, std::string(parts.head) + "\n");
    dir.write("data.raw", parts.tail);
  } else {
    file = dir.write(attached, parts.head);
  }
  try {
    check_volume(read(file));
    accepted("volume");
  } catch (const std::exception& e) {
    refused(e);
  }
  fuzz_region(file, size > 0 ? data[size - 1] : 0, read_header, read_region);
  return 0;
}

}  // namespace imx::fuzz
