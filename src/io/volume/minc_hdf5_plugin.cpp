#include "io/volume/minc_hdf5_plugin.hpp"

#include <mutex>
#include <new>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/registry/plugin_loader.hpp"
#include "minc_hdf5/minc_hdf5_abi.h"

// CMake defines these on this file's command line only (CMakeLists.txt), so that no other
// compile names the build or install folder.
#ifndef IMX_MINC_PLUGIN_BUILT
#define IMX_MINC_PLUGIN_BUILT ""
#endif
#ifndef IMX_MINC_PLUGIN_INSTALLED
#define IMX_MINC_PLUGIN_INSTALLED ""
#endif
#ifndef IMX_MINC_PLUGIN_FROM_BINDIR
#define IMX_MINC_PLUGIN_FROM_BINDIR ""
#endif

namespace imx::detail {

struct MincPlugin {
  imx_minc_hdf5_open_fn open = nullptr;
  imx_minc_hdf5_close_fn close = nullptr;
  imx_minc_hdf5_dataset_fn dataset = nullptr;
  imx_minc_hdf5_text_fn text = nullptr;
  imx_minc_hdf5_numbers_fn numbers = nullptr;
  imx_minc_hdf5_read_fn read = nullptr;
};

namespace {

constexpr PluginPlace kPlace{"an intermix MINC plugin",   "IMX_MINC_PLUGIN",
                             IMX_MINC_PLUGIN_FROM_BINDIR, IMX_MINC_PLUGIN_INSTALLED,
                             IMX_MINC_PLUGIN_BUILT,       IMX_MINC_HDF5_ABI_SYMBOL,
                             IMX_MINC_HDF5_ABI_VERSION};

const MincPlugin& minc_plugin(const std::string& file) {
  // A failure is not kept: a later file tries again (IMX_MINC_PLUGIN may have been set since).
  static std::mutex mutex;
  static MincPlugin loaded;
  std::lock_guard lock(mutex);
  if (loaded.open != nullptr) return loaded;
  std::string tried;
  if (void* handle = open_plugin(kPlace, tried)) {
    auto symbol = [&]<class Fn>(Fn& fn, const char* name) {
      fn = reinterpret_cast<Fn>(plugin_symbol(handle, name));
      return fn != nullptr;
    };
    MincPlugin p;
    if (symbol(p.open, IMX_MINC_HDF5_OPEN_SYMBOL) && symbol(p.close, IMX_MINC_HDF5_CLOSE_SYMBOL) &&
        symbol(p.dataset, IMX_MINC_HDF5_DATASET_SYMBOL) &&
        symbol(p.text, IMX_MINC_HDF5_TEXT_SYMBOL) &&
        symbol(p.numbers, IMX_MINC_HDF5_NUMBERS_SYMBOL) &&
        symbol(p.read, IMX_MINC_HDF5_READ_SYMBOL))
      return loaded = p;
    tried = "a plugin without one of the functions of minc_hdf5_abi.h";
  }
  throw Error(fmt::format(
      "{}: reading MINC-2 needs the MINC plugin, which cannot be loaded (tried: {}); set "
      "IMX_MINC_PLUGIN to the path of libimx_minc_hdf5.so",
      file, tried));
}

int32_t scalar_of(RawType type) {
  switch (type) {
    case RawType::i8:
      return IMX_MINC_HDF5_I8;
    case RawType::u8:
      return IMX_MINC_HDF5_U8;
    case RawType::i16:
      return IMX_MINC_HDF5_I16;
    case RawType::u16:
      return IMX_MINC_HDF5_U16;
    case RawType::i32:
      return IMX_MINC_HDF5_I32;
    case RawType::u32:
      return IMX_MINC_HDF5_U32;
    case RawType::i64:
      return IMX_MINC_HDF5_I64;
    case RawType::u64:
      return IMX_MINC_HDF5_U64;
    case RawType::f32:
      return IMX_MINC_HDF5_F32;
    case RawType::f64:
      return IMX_MINC_HDF5_F64;
  }
  return 0;
}

// The plugin's message.
struct Message {
  char text[4096] = "";
};

// True for OK, false for MISSING; throws for the rest.
bool succeeded(int32_t status, const std::string& file, const Message& error) {
  if (status == IMX_MINC_HDF5_OK) return true;
  if (status == IMX_MINC_HDF5_MISSING) return false;
  if (status == IMX_MINC_HDF5_OUT_OF_MEMORY) throw std::bad_alloc();
  throw Error(fmt::format("{}: {}", file, error.text[0] != '\0' ? error.text : "HDF5 failed"));
}

}  // namespace

std::vector<std::string> minc_plugin_paths() {
  return plugin_paths(kPlace);
}

Hdf5File::Hdf5File(const std::filesystem::path& file, const std::filesystem::path& open_as)
    : name_(file.string()), plugin_(&minc_plugin(name_)) {
  Message error;
  const std::string path = open_as.empty() ? name_ : open_as.string();
  if (!succeeded(plugin_->open(path.c_str(), &file_, error.text, sizeof error.text), name_, error))
    throw Error(fmt::format("{}: HDF5 could not open it", name_));
}

Hdf5File::~Hdf5File() {
  plugin_->close(file_);
}

std::optional<Hdf5Dataset> Hdf5File::dataset(const std::string& object) const {
  imx_minc_hdf5_dataset_info info{};
  Message error;
  if (!succeeded(plugin_->dataset(file_, object.c_str(), &info, error.text, sizeof error.text),
                 name_, error))
    return std::nullopt;
  Hdf5Dataset d;
  d.is_dataset = info.is_dataset != 0;
  if (!d.is_dataset) return d;
  if (info.rank < 0 || info.rank > IMX_MINC_HDF5_MAX_RANK)
    throw Error(
        fmt::format("{}: {}: the MINC plugin gave {} dimensions", name_, object, info.rank));
  d.dims.assign(info.dims, info.dims + info.rank);
  d.element = info.element_class == IMX_MINC_HDF5_INTEGER  ? Hdf5Dataset::Element::integer
              : info.element_class == IMX_MINC_HDF5_FLOAT  ? Hdf5Dataset::Element::floating
              : info.element_class == IMX_MINC_HDF5_STRING ? Hdf5Dataset::Element::string
                                                           : Hdf5Dataset::Element::other;
  d.element_size = info.element_size;
  d.element_signed = info.element_signed != 0;
  return d;
}

std::optional<std::string> Hdf5File::text(const std::string& object, const char* attribute,
                                          size_t max_bytes) const {
  std::string value(max_bytes + 1, '\0');
  Message error;
  if (!succeeded(plugin_->text(file_, object.c_str(), attribute, value.data(), value.size(),
                               error.text, sizeof error.text),
                 name_, error))
    return std::nullopt;
  value.resize(value.find('\0'));
  return value;
}

std::optional<std::vector<double>> Hdf5File::numbers(const std::string& object,
                                                     const char* attribute,
                                                     size_t max_values) const {
  std::vector<double> values(max_values);
  int64_t count = 0;
  Message error;
  if (!succeeded(plugin_->numbers(file_, object.c_str(), attribute, values.data(), values.size(),
                                  &count, error.text, sizeof error.text),
                 name_, error))
    return std::nullopt;
  if (count < 1 || static_cast<size_t>(count) > max_values)
    throw Error(fmt::format("{}: {} attribute '{}': the MINC plugin gave {} values", name_, object,
                            attribute, count));
  values.resize(static_cast<size_t>(count));
  return values;
}

void Hdf5File::read(const std::string& object, RawType type, std::span<const int64_t> start,
                    std::span<const int64_t> count, std::span<uint8_t> out) const {
  Message error;
  if (!succeeded(plugin_->read(file_, object.c_str(), scalar_of(type), start.data(), count.data(),
                               out.data(), out.size(), error.text, sizeof error.text),
                 name_, error))
    throw Error(fmt::format("{}: has no {}", name_, object));
}

}  // namespace imx::detail
