/* The C interface of the MINC-2 plugin (libimx_minc_hdf5.so, built from this folder): libhdf5's
 * reading of the objects a MINC-2 file holds. imx_io opens the plugin with dlopen on the first
 * MINC-2 file (io/volume/minc_hdf5_plugin.cpp), so that libhdf5 (with libcurl, libcrypto and
 * libsz) is not loaded at every start-up; what MINC means (dimension names, placement, scaling,
 * frames) stays in imx_io (io/volume/minc2_reader.cpp). Plain C: paths, numbers, caller buffers
 * and an error string; no C++ type or exception crosses it, and the only thing of the plugin's
 * the caller holds is an open file, given back to imx_minc_hdf5_close.
 *
 * Every object is reached through hard links only, and a dataset whose data lies outside the
 * file (external or virtual storage) is refused, so a file cannot make libhdf5 open another.
 * libhdf5 on Debian is built without thread safety: each call holds the plugin's one mutex. */
#ifndef IMX_MINC_HDF5_ABI_H
#define IMX_MINC_HDF5_ABI_H

#include <stddef.h>
#include <stdint.h>

/* Raised whenever a signature or struct below changes: a plugin of another version is not used. */
#define IMX_MINC_HDF5_ABI_VERSION 1u

#define IMX_MINC_HDF5_ABI_SYMBOL "imx_minc_hdf5_abi"
#define IMX_MINC_HDF5_OPEN_SYMBOL "imx_minc_hdf5_open"
#define IMX_MINC_HDF5_CLOSE_SYMBOL "imx_minc_hdf5_close"
#define IMX_MINC_HDF5_DATASET_SYMBOL "imx_minc_hdf5_dataset"
#define IMX_MINC_HDF5_TEXT_SYMBOL "imx_minc_hdf5_text"
#define IMX_MINC_HDF5_NUMBERS_SYMBOL "imx_minc_hdf5_numbers"
#define IMX_MINC_HDF5_READ_SYMBOL "imx_minc_hdf5_read"

/* The most dimensions a dataset may have. */
#define IMX_MINC_HDF5_MAX_RANK 8

/* The results of every call. */
enum imx_minc_hdf5_status {
  IMX_MINC_HDF5_OK = 0,
  IMX_MINC_HDF5_FAILED = 1,       /* `error` says why, naming the object (not the file) */
  IMX_MINC_HDF5_MISSING = 2,      /* the object (a part of its path) or attribute is not there */
  IMX_MINC_HDF5_OUT_OF_MEMORY = 3 /* an allocation failed */
};

/* A dataset's or attribute's element class. */
enum imx_minc_hdf5_class {
  IMX_MINC_HDF5_OTHER = 0,
  IMX_MINC_HDF5_INTEGER = 1,
  IMX_MINC_HDF5_FLOAT = 2,
  IMX_MINC_HDF5_STRING = 3
};

/* The element types imx_minc_hdf5_read converts to (host order). */
enum imx_minc_hdf5_scalar {
  IMX_MINC_HDF5_U8 = 1,
  IMX_MINC_HDF5_I8,
  IMX_MINC_HDF5_U16,
  IMX_MINC_HDF5_I16,
  IMX_MINC_HDF5_U32,
  IMX_MINC_HDF5_I32,
  IMX_MINC_HDF5_U64,
  IMX_MINC_HDF5_I64,
  IMX_MINC_HDF5_F32,
  IMX_MINC_HDF5_F64
};

/* What imx_minc_hdf5_dataset says of one dataset. */
struct imx_minc_hdf5_dataset_info {
  int32_t is_dataset;                   /* 0: the object is there but is a group or a named type */
  int32_t rank;                         /* 0 .. IMX_MINC_HDF5_MAX_RANK (0: a scalar) */
  int64_t dims[IMX_MINC_HDF5_MAX_RANK]; /* slowest first, each 0 .. INT32_MAX */
  int32_t element_class;                /* an imx_minc_hdf5_class */
  int32_t element_size;                 /* bytes */
  int32_t element_signed;               /* integers: 1 when two's complement */
};

#ifdef __cplusplus
extern "C" {
#endif

/* Returns IMX_MINC_HDF5_ABI_VERSION as the plugin was built. */
typedef uint32_t (*imx_minc_hdf5_abi_fn)(void);

/* Opens the HDF5 file `path` read-only: IMX_MINC_HDF5_OK with *file set (for the calls below and
 * imx_minc_hdf5_close), or another status with a NUL-terminated message in `error` (error_size
 * bytes). The caller has checked the file's size and HDF5 signature first. */
typedef int32_t (*imx_minc_hdf5_open_fn)(const char* path, void** file, char* error,
                                         size_t error_size);

/* Closes what imx_minc_hdf5_open returned (null: nothing). */
typedef void (*imx_minc_hdf5_close_fn)(void* file);

/* Describes the object at the absolute path `object` (e.g. "/minc-2.0/image/0/image"). When it is
 * a dataset, its extent and element type; a dataset whose data is not in the file, with more
 * than IMX_MINC_HDF5_MAX_RANK dimensions or a dimension over INT32_MAX fails. */
typedef int32_t (*imx_minc_hdf5_dataset_fn)(void* file, const char* object,
                                            struct imx_minc_hdf5_dataset_info* info, char* error,
                                            size_t error_size);

/* The string attribute `attribute` of `object` (one string, fixed or variable length), written
 * NUL-terminated to `text` with trailing NULs removed; one longer than text_size - 1 bytes, or an
 * attribute that is not one string, fails. */
typedef int32_t (*imx_minc_hdf5_text_fn)(void* file, const char* object, const char* attribute,
                                         char* text, size_t text_size, char* error,
                                         size_t error_size);

/* The numeric attribute `attribute` of `object` as doubles: *count values (1 .. capacity) written
 * to `values`; an attribute that is not numbers, or holds none or more than `capacity`, fails. */
typedef int32_t (*imx_minc_hdf5_numbers_fn)(void* file, const char* object, const char* attribute,
                                            double* values, size_t capacity, int64_t* count,
                                            char* error, size_t error_size);

/* Reads the hyperslab start[d] .. start[d] + count[d] (d < the dataset's rank) of the dataset
 * `object`, converted by libhdf5 to `scalar` (an imx_minc_hdf5_scalar), row-major into `out`,
 * which holds exactly out_bytes = the product of count times the scalar's size. */
typedef int32_t (*imx_minc_hdf5_read_fn)(void* file, const char* object, int32_t scalar,
                                         const int64_t* start, const int64_t* count, void* out,
                                         size_t out_bytes, char* error, size_t error_size);

#ifdef __cplusplus
}
#endif

#endif
