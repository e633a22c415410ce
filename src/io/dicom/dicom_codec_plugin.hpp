// The DICOM codec plugin (src/dicom_codec/, libimx_dicom_codec.so), opened with dlopen on the
// first file whose pixels need a codec: a series of native little-endian files never loads
// GDCM's dictionary and codecs (about 30 ms of every start-up before they were split off).
#pragma once
#include <string>
#include <vector>

#include "dicom_codec/dicom_codec_abi.h"

namespace imx::detail {

// Where the plugin is looked for, in order: $IMX_DICOM_CODEC alone when it is set; else beside
// the program or module as installed (BINDIR/../LIBDIR/intermix), the install prefix's LIBDIR,
// and the build tree.
std::vector<std::string> dicom_codec_paths();

// The plugin's decode function, loaded once per process (thread-safe); throws imx::Error
// "FILE: ... the DICOM codec plugin cannot be loaded (tried: PATH (why), ...)" naming `file`,
// the file that needs it, when no path gives a plugin of this build's interface version.
imx_dicom_codec_decode_fn dicom_codec(const std::string& file);

}  // namespace imx::detail
