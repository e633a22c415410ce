// Reads the data arrays of a GIfTI file (.gii) that make its surface, checking the whole file on
// the way. intermix decodes GIfTI itself (expat and zlib): libgiftiio sized its buffers from the
// file's claims in int arithmetic, held every array three times over (1 GiB of zeros in a
// 1.4 MB file cost 3.4 GB), filled undecodable data with zeros and wrote to stderr.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace imx::detail {

enum class GiftiType { float32, float64, int8, uint8, int16, uint16, int32, uint32, int64, uint64 };

// Calls fn(T{}) with the C++ type that `type` names (float, double, int8_t, ... uint64_t).
template <class Fn>
decltype(auto) visit_gifti_type(GiftiType type, Fn&& fn) {
  switch (type) {
    case GiftiType::float64:
      return fn(double{});
    case GiftiType::int8:
      return fn(int8_t{});
    case GiftiType::uint8:
      return fn(uint8_t{});
    case GiftiType::int16:
      return fn(int16_t{});
    case GiftiType::uint16:
      return fn(uint16_t{});
    case GiftiType::int32:
      return fn(int32_t{});
    case GiftiType::uint32:
      return fn(uint32_t{});
    case GiftiType::int64:
      return fn(int64_t{});
    case GiftiType::uint64:
      return fn(uint64_t{});
    case GiftiType::float32:
      break;
  }
  return fn(float{});
}

// One rows x 3 data array as the file stores it.
struct GiftiArray {
  GiftiType type = GiftiType::float32;
  uint64_t rows = 0;           // Dim0
  bool column_major = false;   // ColumnMajorOrder: all x (or first indices), then all y, ...
  bool swapped = false;        // in the other byte order than this machine's
  std::vector<uint8_t> bytes;  // rows * 3 values of `type`
};

// One CoordinateSystemTransformMatrix of a data array: the space its values are in (DataSpace),
// another space (TransformedSpace) and the 4x4 map between them (MatrixData, row after row), as
// the file spells them (NIFTI_XFORM_UNKNOWN, _SCANNER_ANAT, _ALIGNED_ANAT, _TALAIRACH, _MNI_152).
struct GiftiCoordinateSystem {
  std::string data_space, transformed_space, matrix;  // the elements' text, trimmed
};

// The first NIFTI_INTENT_POINTSET (floating-point) and NIFTI_INTENT_TRIANGLE (integer) arrays,
// and the POINTSET's coordinate systems in the file's order.
struct GiftiSurface {
  GiftiArray points, triangles;
  std::vector<GiftiCoordinateSystem> coordinate_systems;
};

// One entry of a GIfTI LabelTable: Key (Index in older files; Key where both), Red, Green, Blue,
// Alpha (0..1) and the label's name.
struct GiftiLabel {
  int64_t key = 0;
  float rgba[4] = {1.0f, 1.0f, 1.0f, 1.0f};
  std::string name;
};

// A data array of per-vertex values (func, shape or label files) and the file's label table.
struct GiftiOverlay {
  GiftiArray values;  // rows values (Dim0), one column; `column_major` is irrelevant
  int index = -1;     // which data array of the file
  std::string intent;
  std::vector<GiftiLabel> labels;  // the LabelTable, in the file's order
};

// Parses the XML (expat) and checks it all: the elements nest as GIfTI's do, no entities, and
// every data array has a numeric type, 1 to 6 dimensions of at most 1 GiB, and ASCII,
// Base64Binary or GZipBase64Binary data (by any name nibabel knows: B64BIN, GIFTI_ENCODING_B64GZ,
// ...) in the file itself holding exactly the values its dimensions claim. ASCII data in
// ColumnMajorOrder a row a line (as nibabel writes and reads it, whatever the order) is rows;
// in any other layout (a column a line, as libgiftiio writes it) it is in column order; on 3
// lines of 3 values, which could be either, it is refused. A file of values alone (no POINTSET) is
// refused as an overlay that needs its surface. Before any data is decoded, the claim must be one
// the rest of the file can hold (for compressed data, at deflate's largest ratio, kMaxInflateRatio)
// and, for the two arrays kept, fit the memory budget (check_memory) with the mesh made from them;
// compressed data is inflated to the claim, never past it. Other arrays are checked as they stream
// by and not kept; their compressed data is not inflated (deflate can expand 1032 times: 2.5 s of
// work for each MB of a file), only its size held to the claim. Throws imx::Error naming the
// file, the array and the fault.
GiftiSurface read_gifti_arrays(const std::filesystem::path& file);

// The same checks, keeping data array `array` (an index into the file's arrays), or with -1 the
// first whose intent is not POINTSET, TRIANGLE or VECTOR: it must have one dimension, or two
// with Dim1 1. Files of sparse data (NIFTI_INTENT_NODE_INDEX) are refused.
GiftiOverlay read_gifti_overlay(const std::filesystem::path& file, int array);

}  // namespace imx::detail
