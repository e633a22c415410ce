// The DICOM codec plugin: GDCM's ImageReader decodes one file's pixels (JPEG, JPEG-LS,
// JPEG 2000, RLE, deflate, big-endian), behind the C interface of dicom_codec_abi.h. imx_io
// opens it on first use (io/dicom/dicom_codec_plugin.cpp) and calls it in its decoder processes.
#include "dicom_codec/dicom_codec_abi.h"

#include <cstdio>
#include <exception>

#include <gdcmImageReader.h>

namespace {

// The message, cut to the room the caller gave.
template <class... Args>
int32_t fail(int32_t status, char* error, size_t error_size, const char* format, Args... args) {
  if (error != nullptr && error_size > 0) std::snprintf(error, error_size, format, args...);
  return status;
}

// The plugin's type of a GDCM scalar type; 0 for one intermix does not read.
int32_t scalar_of(gdcm::PixelFormat::ScalarType type, uint64_t& size) {
  switch (type) {
    case gdcm::PixelFormat::UINT8:
      size = 1;
      return IMX_DICOM_CODEC_U8;
    case gdcm::PixelFormat::INT8:
      size = 1;
      return IMX_DICOM_CODEC_I8;
    case gdcm::PixelFormat::UINT16:
      size = 2;
      return IMX_DICOM_CODEC_U16;
    case gdcm::PixelFormat::INT16:
      size = 2;
      return IMX_DICOM_CODEC_I16;
    case gdcm::PixelFormat::UINT32:
      size = 4;
      return IMX_DICOM_CODEC_U32;
    case gdcm::PixelFormat::INT32:
      size = 4;
      return IMX_DICOM_CODEC_I32;
    case gdcm::PixelFormat::FLOAT32:
      size = 4;
      return IMX_DICOM_CODEC_F32;
    case gdcm::PixelFormat::FLOAT64:
      size = 8;
      return IMX_DICOM_CODEC_F64;
    default:
      return 0;
  }
}

int32_t decode(const char* path, uint32_t columns, uint32_t rows, uint32_t frames, void* pixels,
               uint64_t room, imx_dicom_codec_format* out, char* error, size_t error_size) {
  gdcm::ImageReader reader;
  reader.SetFileName(path);
  bool read = false;
  try {
    read = reader.Read();
  } catch (...) {
    read = false;
  }
  if (!read)
    return fail(IMX_DICOM_CODEC_REFUSED, error, error_size, "%s",
                "GDCM cannot read the image (truncated or corrupt file, or an unsupported "
                "encoding)");
  const gdcm::Image& image = reader.GetImage();
  const gdcm::PixelFormat& pf = image.GetPixelFormat();
  if (pf.GetSamplesPerPixel() != 1)
    return fail(IMX_DICOM_CODEC_REFUSED, error, error_size,
                "unsupported photometric interpretation: %u samples per pixel (colour); only "
                "greyscale images are read",
                static_cast<unsigned>(pf.GetSamplesPerPixel()));
  const unsigned image_frames = image.GetNumberOfDimensions() >= 3 ? image.GetDimension(2) : 1;
  if (image.GetColumns() != columns || image.GetRows() != rows || image_frames != frames)
    return fail(IMX_DICOM_CODEC_REFUSED, error, error_size,
                "the image is %ux%ux%u, the header says %ux%ux%u", image.GetColumns(),
                image.GetRows(), image_frames, columns, rows, frames);
  uint64_t size = 0;
  const int32_t scalar = scalar_of(pf.GetScalarType(), size);
  if (scalar == 0)
    return fail(IMX_DICOM_CODEC_REFUSED, error, error_size,
                "unsupported pixel format (BitsAllocated %u, PixelRepresentation %u)",
                static_cast<unsigned>(pf.GetBitsAllocated()),
                static_cast<unsigned>(pf.GetPixelRepresentation()));
  const uint64_t expected = uint64_t{columns} * rows * frames * size;
  const uint64_t length = image.GetBufferLength();
  if (length != expected || length > room)
    return fail(IMX_DICOM_CODEC_REFUSED, error, error_size,
                "GDCM reports %llu bytes of pixels, expected %llu",
                static_cast<unsigned long long>(length), static_cast<unsigned long long>(expected));
  bool decoded = false;
  try {
    decoded = image.GetBuffer(static_cast<char*>(pixels));
  } catch (...) {
    decoded = false;
  }
  if (!decoded) return fail(IMX_DICOM_CODEC_CORRUPT, error, error_size, "%s", "corrupt");
  out->scalar = scalar;
  out->bits_stored = pf.GetBitsStored();
  out->high_bit = pf.GetHighBit();
  return IMX_DICOM_CODEC_OK;
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) uint32_t imx_dicom_codec_abi(void) {
  return IMX_DICOM_CODEC_ABI_VERSION;
}

__attribute__((visibility("default"))) int32_t imx_dicom_codec_decode(
    const char* path, uint32_t columns, uint32_t rows, uint32_t frames, void* pixels, uint64_t room,
    imx_dicom_codec_format* format, char* error, size_t error_size) {
  if (error != nullptr && error_size > 0) error[0] = '\0';
  // Nothing thrown leaves the plugin: the caller is C.
  try {
    return decode(path, columns, rows, frames, pixels, room, format, error, error_size);
  } catch (const std::exception& e) {
    return fail(IMX_DICOM_CODEC_REFUSED, error, error_size, "the DICOM codec failed: %s", e.what());
  } catch (...) {
    return fail(IMX_DICOM_CODEC_REFUSED, error, error_size, "%s", "the DICOM codec failed");
  }
}
}

// The definitions have the interface's signatures (imx_io calls them through these types).
[[maybe_unused]] constexpr imx_dicom_codec_abi_fn imx_abi_signature = &imx_dicom_codec_abi;
[[maybe_unused]] constexpr imx_dicom_codec_decode_fn imx_decode_signature = &imx_dicom_codec_decode;
