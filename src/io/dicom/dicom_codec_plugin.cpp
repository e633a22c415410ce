#include "io/dicom/dicom_codec_plugin.hpp"

#include <mutex>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/registry/plugin_loader.hpp"

// CMake defines these on this file's command line only (CMakeLists.txt), so that no other
// compile names the build or install folder.
#ifndef IMX_DICOM_CODEC_BUILT
#define IMX_DICOM_CODEC_BUILT ""
#endif
#ifndef IMX_DICOM_CODEC_INSTALLED
#define IMX_DICOM_CODEC_INSTALLED ""
#endif
#ifndef IMX_DICOM_CODEC_FROM_BINDIR
#define IMX_DICOM_CODEC_FROM_BINDIR ""
#endif

namespace imx::detail {

namespace {

constexpr PluginPlace kPlace{
    "an intermix DICOM codec plugin", "IMX_DICOM_CODEC",     IMX_DICOM_CODEC_FROM_BINDIR,
    IMX_DICOM_CODEC_INSTALLED,        IMX_DICOM_CODEC_BUILT, IMX_DICOM_CODEC_ABI_SYMBOL,
    IMX_DICOM_CODEC_ABI_VERSION};

}  // namespace

std::vector<std::string> dicom_codec_paths() {
  return plugin_paths(kPlace);
}

imx_dicom_codec_decode_fn dicom_codec(const std::string& file) {
  // A failure is not kept: a later file tries again (IMX_DICOM_CODEC may have been set since).
  static std::mutex mutex;
  static imx_dicom_codec_decode_fn loaded = nullptr;
  std::lock_guard lock(mutex);
  if (loaded != nullptr) return loaded;
  std::string tried;
  if (void* handle = open_plugin(kPlace, tried)) {
    loaded = reinterpret_cast<imx_dicom_codec_decode_fn>(
        plugin_symbol(handle, IMX_DICOM_CODEC_DECODE_SYMBOL));
    if (loaded != nullptr) return loaded;
    tried = "a plugin without " IMX_DICOM_CODEC_DECODE_SYMBOL;
  }
  throw Error(fmt::format(
      "{}: its pixel data needs the DICOM codec plugin, which cannot be loaded (tried: {}); set "
      "IMX_DICOM_CODEC to the path of libimx_dicom_codec.so",
      file, tried));
}

}  // namespace imx::detail
