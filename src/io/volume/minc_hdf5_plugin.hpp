// The MINC-2 plugin (src/minc_hdf5/, libimx_minc_hdf5.so), opened with dlopen on the first MINC-2
// file: nothing else loads libhdf5 (and libcurl, libcrypto, libsz with it), which would cost
// every start-up their loading and relocation. This is its C++ side: one open HDF5 file whose
// objects and attributes the MINC-2 reader asks for by path.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "io/voxels/raw_voxels.hpp"

namespace imx::detail {

// Where the plugin is looked for, in order: $IMX_MINC_PLUGIN alone when it is set; else beside
// the program or module as installed (BINDIR/../LIBDIR/intermix), the install prefix's LIBDIR,
// and the build tree.
std::vector<std::string> minc_plugin_paths();

// What the plugin says of an HDF5 object.
struct Hdf5Dataset {
  enum class Element { other, integer, floating, string };
  bool is_dataset = false;    // false: a group or a named type (nothing below is set)
  std::vector<int64_t> dims;  // slowest first, each 0 .. INT32_MAX; empty for a scalar
  Element element = Element::other;
  int element_size = 0;         // bytes
  bool element_signed = false;  // integers
};

struct MincPlugin;  // the plugin's functions

// An HDF5 file opened read-only through the plugin (loaded once per process, thread-safe). Every
// object is reached through hard links only, and data kept outside the file is refused. Failures
// throw imx::Error "FILE: OBJECT ...: why" (the plugin's message), std::bad_alloc when memory
// runs out; a plugin that cannot be loaded is "FILE: ... the MINC plugin, which cannot be loaded
// (tried: PATH (why), ...)".
class Hdf5File {
 public:
  // The caller has checked the file's size and HDF5 signature: libhdf5 parses what it is given.
  // `open_as` (a /proc/self/fd path of the guarded open) is what HDF5 opens; `file` names it.
  explicit Hdf5File(const std::filesystem::path& file, const std::filesystem::path& open_as = {});
  ~Hdf5File();
  Hdf5File(const Hdf5File&) = delete;
  Hdf5File& operator=(const Hdf5File&) = delete;

  // The object at the absolute path `object`; nullopt when it (or a part of its path) is not there.
  std::optional<Hdf5Dataset> dataset(const std::string& object) const;
  // A string attribute of at most `max_bytes` bytes (trailing NULs removed); nullopt when absent.
  std::optional<std::string> text(const std::string& object, const char* attribute,
                                  size_t max_bytes) const;
  // A numeric attribute of 1 .. `max_values` values; nullopt when absent.
  std::optional<std::vector<double>> numbers(const std::string& object, const char* attribute,
                                             size_t max_values) const;
  // The hyperslab start .. start + count (one entry per dim of the dataset) as `type`, row-major,
  // into `out`, which holds exactly the hyperslab.
  void read(const std::string& object, RawType type, std::span<const int64_t> start,
            std::span<const int64_t> count, std::span<uint8_t> out) const;

  // The file, for messages.
  const std::string& name() const { return name_; }

 private:
  std::string name_;
  const MincPlugin* plugin_;
  void* file_ = nullptr;
};

}  // namespace imx::detail
