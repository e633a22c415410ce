/* The C interface of the DICOM codec plugin (libimx_dicom_codec.so, built from this folder).
 * imx_io opens the plugin with dlopen on the first file whose pixels need a codec (a compressed
 * or big-endian transfer syntax), so that GDCM's dictionary and codecs (libgdcmMSFF, DICT, IOD,
 * the JPEG, JPEG-LS and JPEG 2000 libraries: about 30 ms of start-up) load only then. Plain C:
 * buffers, sizes and an error string; no C++ type or exception crosses it. */
#ifndef IMX_DICOM_CODEC_ABI_H
#define IMX_DICOM_CODEC_ABI_H

#include <stddef.h>
#include <stdint.h>

/* Raised whenever a signature or struct below changes: a plugin of another version is not used. */
#define IMX_DICOM_CODEC_ABI_VERSION 1u

#define IMX_DICOM_CODEC_ABI_SYMBOL "imx_dicom_codec_abi"
#define IMX_DICOM_CODEC_DECODE_SYMBOL "imx_dicom_codec_decode"

/* The type of the decoded values, as GDCM gives them (BitsAllocated per value, host order). */
enum imx_dicom_codec_scalar {
  IMX_DICOM_CODEC_U8 = 1,
  IMX_DICOM_CODEC_I8,
  IMX_DICOM_CODEC_U16,
  IMX_DICOM_CODEC_I16,
  IMX_DICOM_CODEC_U32,
  IMX_DICOM_CODEC_I32,
  IMX_DICOM_CODEC_F32,
  IMX_DICOM_CODEC_F64
};

/* What the plugin says of the pixels it decoded. */
struct imx_dicom_codec_format {
  int32_t scalar; /* an imx_dicom_codec_scalar */
  int32_t bits_stored;
  int32_t high_bit;
};

/* imx_dicom_codec_decode's results. */
enum imx_dicom_codec_status {
  IMX_DICOM_CODEC_OK = 0,
  IMX_DICOM_CODEC_REFUSED = 1, /* `error` says why (without the file's name) */
  IMX_DICOM_CODEC_CORRUPT = 2  /* the codec failed on the pixel data */
};

#ifdef __cplusplus
extern "C" {
#endif

/* Returns IMX_DICOM_CODEC_ABI_VERSION as the plugin was built. */
typedef uint32_t (*imx_dicom_codec_abi_fn)(void);

/* Decodes the pixels of the DICOM file `path`, which must hold columns x rows x frames
 * single-sample values, into `pixels` (room: `room` bytes): returns IMX_DICOM_CODEC_OK and sets
 * *format, or another status with a NUL-terminated message in `error` (error_size bytes). */
typedef int32_t (*imx_dicom_codec_decode_fn)(const char* path, uint32_t columns, uint32_t rows,
                                             uint32_t frames, void* pixels, uint64_t room,
                                             struct imx_dicom_codec_format* format, char* error,
                                             size_t error_size);

#ifdef __cplusplus
}
#endif

#endif
