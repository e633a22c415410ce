#include "io/gifti_reader.hpp"

// Debian's gifti_io.h declares C functions without extern "C".
extern "C" {
#include <gifti_io.h>
}

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <mutex>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/gifti_check.hpp"

namespace imx::detail {
namespace {

// libgiftiio keeps its parser state in globals.
std::mutex& gifti_mutex() {
  static std::mutex m;
  return m;
}

// Value i of an array of the given NIfTI type (libgiftiio has swapped it to this machine).
double value_at(const giiDataArray& da, size_t i) {
  const auto* p = static_cast<const unsigned char*>(da.data);
  auto load = [&]<class T>(T) {
    T v;
    std::memcpy(&v, p + i * sizeof(T), sizeof(T));
    return static_cast<double>(v);
  };
  switch (da.datatype) {
    case NIFTI_TYPE_FLOAT32:
      return load(float{});
    case NIFTI_TYPE_FLOAT64:
      return load(double{});
    case NIFTI_TYPE_INT8:
      return load(int8_t{});
    case NIFTI_TYPE_UINT8:
      return load(uint8_t{});
    case NIFTI_TYPE_INT16:
      return load(int16_t{});
    case NIFTI_TYPE_UINT16:
      return load(uint16_t{});
    case NIFTI_TYPE_INT32:
      return load(int32_t{});
    case NIFTI_TYPE_UINT32:
      return load(uint32_t{});
    case NIFTI_TYPE_INT64:
      return load(int64_t{});
    case NIFTI_TYPE_UINT64:
      return load(uint64_t{});
    default:
      return 0.0;  // check_gifti admits no other type
  }
}

// Element (row, col) of a rows x 3 array in the file's index order.
double element(const giiDataArray& da, size_t row, size_t col) {
  const size_t rows = static_cast<size_t>(da.dims[0]);
  return value_at(da, da.ind_ord == GIFTI_IND_ORD_COL_MAJOR ? col * rows + row : row * 3 + col);
}

}  // namespace

Mesh read_gifti(const std::filesystem::path& file) {
  const GiftiSurfaceArrays arrays = check_gifti(file);
  auto fail = [&](const std::string& why) {
    throw Error(fmt::format("{}: {}", file.string(), why));
  };

  std::lock_guard lock(gifti_mutex());
  gifti_set_verb(0);
  // Every array is read: libgiftiio's list of arrays to read crashes on the ones it skips.
  std::unique_ptr<gifti_image, decltype(&gifti_free_image)> image(
      gifti_read_image(file.string().c_str(), 1), &gifti_free_image);
  if (!image || !image->darray || image->numDA <= std::max(arrays.pointset, arrays.triangle))
    fail("libgiftiio cannot read the file");
  const giiDataArray* points = image->darray[arrays.pointset];
  const giiDataArray* triangles = image->darray[arrays.triangle];
  if (!points || points->intent != NIFTI_INTENT_POINTSET || !triangles ||
      triangles->intent != NIFTI_INTENT_TRIANGLE)
    fail("libgiftiio found other data arrays than the file holds");
  for (const giiDataArray* da : {points, triangles})
    if (!da->data || da->num_dim != 2 || da->dims[1] != 3 || da->dims[0] <= 0 ||
        da->nvals != int64_t{da->dims[0]} * 3)
      fail("libgiftiio returned a POINTSET or TRIANGLE array unlike the one in the file");

  Mesh mesh;
  const size_t n_points = static_cast<size_t>(points->dims[0]);
  mesh.positions.reserve(n_points);
  for (size_t i = 0; i < n_points; ++i)
    mesh.positions.emplace_back(element(*points, i, 0), element(*points, i, 1),
                                element(*points, i, 2));
  const size_t n_triangles = static_cast<size_t>(triangles->dims[0]);
  mesh.triangles.reserve(n_triangles);
  for (size_t f = 0; f < n_triangles; ++f) {
    glm::uvec3 t;
    for (int c = 0; c < 3; ++c) {
      const double v = element(*triangles, f, static_cast<size_t>(c));
      if (!(v >= 0.0 && v < static_cast<double>(n_points)))
        fail(fmt::format("triangle {} uses vertex {:.0f}, but the file has {} vertices", f, v,
                         n_points));
      t[c] = static_cast<uint32_t>(v);
    }
    mesh.triangles.push_back(t);
  }
  return mesh;
}

}  // namespace imx::detail
