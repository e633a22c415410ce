// The MINC-2 plugin: libhdf5 reads the objects of a MINC-2 file behind the C interface of
// minc_hdf5_abi.h. imx_io checks the file first (its size, HDF5's signature) and makes sense of
// what this gives (io/volume/minc2_reader.cpp).
//
// libhdf5 is not hardened against hostile files: the reader is fuzzed (fuzz/fuzz_minc.cpp), every
// object is reached through hard links only and must keep its data in the file, and every count
// is checked against the caller's buffer before anything is read into it.
#include "minc_hdf5/minc_hdf5_abi.h"

#include <hdf5.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <mutex>
#include <new>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

// libhdf5 on Debian is built without thread safety: every call into it holds this.
std::mutex hdf5_mutex;

// What a call fails with: the status and, for IMX_MINC_HDF5_FAILED, the message.
struct Failure {
  int32_t status;
  std::string message;
};

[[noreturn]] void fail(const std::string& where, const std::string& message) {
  throw Failure{IMX_MINC_HDF5_FAILED, where + ": " + message};
}

[[noreturn]] void missing() {
  throw Failure{IMX_MINC_HDF5_MISSING, ""};
}

void check(herr_t status, const std::string& where, const char* action) {
  if (status < 0) fail(where, std::string("HDF5 could not ") + action + " (corrupt file?)");
}

// An HDF5 identifier, closed with its kind's close function.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

// The object at the absolute `path`, reached through hard links only; MISSING when a part of the
// path is not there.
hid_t open_object(hid_t file, const std::string& path) {
  if (path.empty() || path[0] != '/') fail(path, "is not an absolute path");
  size_t at = 1;
  while (at <= path.size()) {
    const size_t slash = std::min(path.find('/', at), path.size());
    const std::string prefix = path.substr(0, slash);
    if (H5Lexists(file, prefix.c_str(), H5P_DEFAULT) <= 0) missing();
    H5L_info_t info;
    check(H5Lget_info(file, prefix.c_str(), &info, H5P_DEFAULT), prefix, "read the link");
    if (info.type != H5L_TYPE_HARD) fail(prefix, "is a soft or external link: not supported");
    at = slash + 1;
  }
  const hid_t id = H5Oopen(file, path.c_str(), H5P_DEFAULT);
  if (id < 0) fail(path, "HDF5 could not open it (corrupt file?)");
  return id;
}

// A dataspace's extent, checked to be few dims of at most INT32_MAX elements.
int32_t extent(hid_t space, int64_t* dims, const std::string& where) {
  const int rank = H5Sget_simple_extent_ndims(space);
  if (rank < 0 || rank > IMX_MINC_HDF5_MAX_RANK)
    fail(where, "has " + std::to_string(rank) + " dimensions");
  hsize_t extent[IMX_MINC_HDF5_MAX_RANK] = {};
  if (H5Sget_simple_extent_dims(space, extent, nullptr) < 0)
    fail(where, "HDF5 could not read its extent (corrupt file?)");
  for (int d = 0; d < rank; ++d) {
    if (extent[d] > static_cast<hsize_t>(std::numeric_limits<int32_t>::max()))
      fail(where,
           "dimension " + std::to_string(d) + " has " + std::to_string(extent[d]) + " elements");
    dims[d] = static_cast<int64_t>(extent[d]);
  }
  return rank;
}

// Refuses a dataset whose data is not in the file: libhdf5 would open the files it names.
void require_data_in_file(hid_t dataset, const std::string& path) {
  Handle plist(H5Dget_create_plist(dataset), H5Pclose);
  if (!plist.valid()) fail(path, "HDF5 could not read its properties (corrupt file?)");
  const H5D_layout_t storage = H5Pget_layout(plist.get());
  if ((storage != H5D_CONTIGUOUS && storage != H5D_CHUNKED && storage != H5D_COMPACT) ||
      H5Pget_external_count(plist.get()) != 0)
    fail(path, "keeps its data outside the file (external or virtual storage)");
}

void describe(hid_t file, const std::string& path, imx_minc_hdf5_dataset_info& info) {
  info = imx_minc_hdf5_dataset_info{};
  Handle dataset(open_object(file, path), H5Oclose);
  if (H5Iget_type(dataset.get()) != H5I_DATASET) return;
  info.is_dataset = 1;
  require_data_in_file(dataset.get(), path);
  Handle space(H5Dget_space(dataset.get()), H5Sclose);
  if (!space.valid()) fail(path, "HDF5 could not read its extent (corrupt file?)");
  info.rank = extent(space.get(), info.dims, path);
  Handle type(H5Dget_type(dataset.get()), H5Tclose);
  if (!type.valid()) fail(path, "HDF5 could not read its type (corrupt file?)");
  const H5T_class_t kind = H5Tget_class(type.get());
  info.element_class = kind == H5T_INTEGER  ? IMX_MINC_HDF5_INTEGER
                       : kind == H5T_FLOAT  ? IMX_MINC_HDF5_FLOAT
                       : kind == H5T_STRING ? IMX_MINC_HDF5_STRING
                                            : IMX_MINC_HDF5_OTHER;
  info.element_size = static_cast<int32_t>(std::min<size_t>(H5Tget_size(type.get()), 1u << 30));
  info.element_signed = kind == H5T_INTEGER && H5Tget_sign(type.get()) == H5T_SGN_2 ? 1 : 0;
}

// The attribute `name` of the object at `path`, with its type and extent.
struct Attribute {
  Attribute(hid_t file, const std::string& path, const char* name)
      : where(path + " attribute '" + name + "'"),
        object(open_object(file, path), H5Oclose),
        attribute(H5Aexists(object.get(), name) > 0 ? H5Aopen(object.get(), name, H5P_DEFAULT) : -1,
                  H5Aclose),
        type(attribute.valid() ? H5Aget_type(attribute.get()) : -1, H5Tclose),
        space(attribute.valid() ? H5Aget_space(attribute.get()) : -1, H5Sclose) {
    if (!attribute.valid()) missing();
    if (!type.valid() || !space.valid()) fail(where, "HDF5 could not read it (corrupt file?)");
  }
  std::string where;
  Handle object, attribute, type, space;
};

void read_text(hid_t file, const std::string& path, const char* name, char* text,
               size_t text_size) {
  Attribute a(file, path, name);
  if (H5Tget_class(a.type.get()) != H5T_STRING) fail(a.where, "is not a string");
  if (H5Sget_simple_extent_npoints(a.space.get()) != 1) fail(a.where, "is not one string");
  const size_t limit = text_size - 1;
  std::string value;
  Handle memory(H5Tcopy(H5T_C_S1), H5Tclose);
  if (!memory.valid()) fail(a.where, "HDF5 could not read it (corrupt file?)");
  if (H5Tis_variable_str(a.type.get()) > 0) {
    check(H5Tset_size(memory.get(), H5T_VARIABLE), a.where, "read it");
    char* read = nullptr;
    check(H5Aread(a.attribute.get(), memory.get(), &read), a.where, "read it");
    if (read != nullptr) {
      value.assign(read, strnlen(read, limit + 1));
      H5free_memory(read);
    }
  } else {
    const size_t size = H5Tget_size(a.type.get());
    if (size == 0 || size > limit)
      fail(a.where, "is a string of " + std::to_string(size) + " bytes");
    // One byte more than the file's: a NUL-terminated copy keeps all of a NUL-padded string.
    check(H5Tset_size(memory.get(), size + 1), a.where, "read it");
    value.assign(size + 1, '\0');
    check(H5Aread(a.attribute.get(), memory.get(), value.data()), a.where, "read it");
  }
  value.resize(strnlen(value.c_str(), value.size()));
  if (value.size() > limit) fail(a.where, "is too long");
  std::memcpy(text, value.c_str(), value.size() + 1);
}

int64_t read_numbers(hid_t file, const std::string& path, const char* name, double* values,
                     size_t capacity) {
  Attribute a(file, path, name);
  const H5T_class_t kind = H5Tget_class(a.type.get());
  if (kind != H5T_INTEGER && kind != H5T_FLOAT) fail(a.where, "is not a number");
  const hssize_t count = H5Sget_simple_extent_npoints(a.space.get());
  if (count < 1 || static_cast<size_t>(count) > capacity)
    fail(a.where, "holds " + std::to_string(count) + " values");
  // Read into a buffer of the attribute's own size: `values` may be larger.
  std::vector<double> read(static_cast<size_t>(count));
  check(H5Aread(a.attribute.get(), H5T_NATIVE_DOUBLE, read.data()), a.where, "read it");
  std::copy(read.begin(), read.end(), values);
  return count;
}

hid_t memory_type(int32_t scalar, size_t& size) {
  switch (scalar) {
    case IMX_MINC_HDF5_U8:
      size = 1;
      return H5T_NATIVE_UINT8;
    case IMX_MINC_HDF5_I8:
      size = 1;
      return H5T_NATIVE_INT8;
    case IMX_MINC_HDF5_U16:
      size = 2;
      return H5T_NATIVE_UINT16;
    case IMX_MINC_HDF5_I16:
      size = 2;
      return H5T_NATIVE_INT16;
    case IMX_MINC_HDF5_U32:
      size = 4;
      return H5T_NATIVE_UINT32;
    case IMX_MINC_HDF5_I32:
      size = 4;
      return H5T_NATIVE_INT32;
    case IMX_MINC_HDF5_U64:
      size = 8;
      return H5T_NATIVE_UINT64;
    case IMX_MINC_HDF5_I64:
      size = 8;
      return H5T_NATIVE_INT64;
    case IMX_MINC_HDF5_F32:
      size = 4;
      return H5T_NATIVE_FLOAT;
    case IMX_MINC_HDF5_F64:
      size = 8;
      return H5T_NATIVE_DOUBLE;
    default:
      throw std::invalid_argument("unknown element type " + std::to_string(scalar));
  }
}

void read_slab(hid_t file, const std::string& path, int32_t scalar, const int64_t* start,
               const int64_t* count, void* out, size_t out_bytes) {
  size_t element = 0;
  const hid_t memory = memory_type(scalar, element);
  Handle dataset(open_object(file, path), H5Oclose);
  if (H5Iget_type(dataset.get()) != H5I_DATASET) fail(path, "is not a dataset");
  require_data_in_file(dataset.get(), path);
  Handle space(H5Dget_space(dataset.get()), H5Sclose);
  if (!space.valid()) fail(path, "HDF5 could not read its extent (corrupt file?)");
  int64_t dims[IMX_MINC_HDF5_MAX_RANK] = {};
  const int32_t rank = extent(space.get(), dims, path);
  hsize_t from[IMX_MINC_HDF5_MAX_RANK] = {}, size[IMX_MINC_HDF5_MAX_RANK] = {};
  size_t bytes = element;
  bool fits = true;
  for (int32_t d = 0; d < rank; ++d) {
    if (start[d] < 0 || count[d] < 1 || start[d] > dims[d] - count[d])
      throw std::invalid_argument(path + ": the hyperslab to read lies outside the dataset");
    from[d] = static_cast<hsize_t>(start[d]);
    size[d] = static_cast<hsize_t>(count[d]);
    fits = fits && static_cast<size_t>(count[d]) <= out_bytes / bytes;  // no overflow below
    if (fits) bytes *= static_cast<size_t>(count[d]);
  }
  if (!fits || bytes != out_bytes)
    throw std::invalid_argument(path + ": the buffer does not fit the hyperslab to read");
  if (rank == 0) {  // a scalar: one element, no selection
    check(H5Dread(dataset.get(), memory, H5S_ALL, H5S_ALL, H5P_DEFAULT, out), path,
          "read its data");
    return;
  }
  Handle selection(H5Screate_simple(rank, size, nullptr), H5Sclose);
  if (!selection.valid() ||
      H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, from, nullptr, size, nullptr) < 0)
    fail(path, "HDF5 could not select the data to read (corrupt file?)");
  check(H5Dread(dataset.get(), memory, selection.get(), space.get(), H5P_DEFAULT, out), path,
        "read its data");
}

void set_error(char* error, size_t error_size, const std::string& message) {
  if (error != nullptr && error_size > 0) std::snprintf(error, error_size, "%s", message.c_str());
}

// Runs `body` under the HDF5 mutex; nothing thrown leaves the plugin (the caller is C).
template <class Body>
int32_t guarded(char* error, size_t error_size, Body&& body) {
  set_error(error, error_size, "");
  try {
    std::lock_guard lock(hdf5_mutex);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // failures are one message, not a stack
    body();
    return IMX_MINC_HDF5_OK;
  } catch (const Failure& f) {
    set_error(error, error_size, f.message);
    return f.status;
  } catch (const std::bad_alloc&) {
    return IMX_MINC_HDF5_OUT_OF_MEMORY;
  } catch (const std::exception& e) {
    set_error(error, error_size, e.what());
  } catch (...) {
    set_error(error, error_size, "HDF5 failed");
  }
  return IMX_MINC_HDF5_FAILED;
}

hid_t file_id(void* file) {
  return static_cast<hid_t>(reinterpret_cast<intptr_t>(file));
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) uint32_t imx_minc_hdf5_abi(void) {
  return IMX_MINC_HDF5_ABI_VERSION;
}

// The open file is HDF5's own identifier, carried in the pointer: the plugin allocates nothing.
static_assert(sizeof(hid_t) <= sizeof(void*));

__attribute__((visibility("default"))) int32_t imx_minc_hdf5_open(const char* path, void** file,
                                                                  char* error, size_t error_size) {
  *file = nullptr;
  return guarded(error, error_size, [&] {
    const hid_t id = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (id < 0)
      throw Failure{IMX_MINC_HDF5_FAILED,
                    "HDF5 could not open it (corrupt or "
                    "truncated file?)"};
    *file = reinterpret_cast<void*>(static_cast<intptr_t>(id));
  });
}

__attribute__((visibility("default"))) void imx_minc_hdf5_close(void* file) {
  if (file == nullptr) return;
  std::lock_guard lock(hdf5_mutex);
  H5Fclose(file_id(file));
}

__attribute__((visibility("default"))) int32_t imx_minc_hdf5_dataset(
    void* file, const char* object, imx_minc_hdf5_dataset_info* info, char* error,
    size_t error_size) {
  return guarded(error, error_size, [&] { describe(file_id(file), object, *info); });
}

__attribute__((visibility("default"))) int32_t imx_minc_hdf5_text(void* file, const char* object,
                                                                  const char* attribute, char* text,
                                                                  size_t text_size, char* error,
                                                                  size_t error_size) {
  if (text == nullptr || text_size == 0) return IMX_MINC_HDF5_FAILED;
  text[0] = '\0';
  return guarded(error, error_size,
                 [&] { read_text(file_id(file), object, attribute, text, text_size); });
}

__attribute__((visibility("default"))) int32_t imx_minc_hdf5_numbers(
    void* file, const char* object, const char* attribute, double* values, size_t capacity,
    int64_t* count, char* error, size_t error_size) {
  *count = 0;
  return guarded(error, error_size, [&] {
    *count = read_numbers(file_id(file), object, attribute, values, capacity);
  });
}

__attribute__((visibility("default"))) int32_t imx_minc_hdf5_read(
    void* file, const char* object, int32_t scalar, const int64_t* start, const int64_t* count,
    void* out, size_t out_bytes, char* error, size_t error_size) {
  return guarded(error, error_size,
                 [&] { read_slab(file_id(file), object, scalar, start, count, out, out_bytes); });
}
}

// The definitions have the interface's signatures (imx_io calls them through these types).
[[maybe_unused]] constexpr imx_minc_hdf5_abi_fn imx_abi_signature = &imx_minc_hdf5_abi;
[[maybe_unused]] constexpr imx_minc_hdf5_open_fn imx_open_signature = &imx_minc_hdf5_open;
[[maybe_unused]] constexpr imx_minc_hdf5_close_fn imx_close_signature = &imx_minc_hdf5_close;
[[maybe_unused]] constexpr imx_minc_hdf5_dataset_fn imx_dataset_signature = &imx_minc_hdf5_dataset;
[[maybe_unused]] constexpr imx_minc_hdf5_text_fn imx_text_signature = &imx_minc_hdf5_text;
[[maybe_unused]] constexpr imx_minc_hdf5_numbers_fn imx_numbers_signature = &imx_minc_hdf5_numbers;
[[maybe_unused]] constexpr imx_minc_hdf5_read_fn imx_read_signature = &imx_minc_hdf5_read;
