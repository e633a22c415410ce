// The OME-XML of an OME-TIFF (its first page's ImageDescription): the first image's Pixels
// element, its sizes, dimension order, type, physical sizes and the TiffData that say which
// page holds which plane.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace imx::detail {

// The most bytes of OME-XML read: a plane list of a million planes is still below it.
inline constexpr size_t kMaxOmeXmlBytes = size_t{64} << 20;

struct OmeTiffData {
  std::optional<int64_t> ifd, plane_count;
  int64_t first_z = 0, first_c = 0, first_t = 0;
  std::string file_name;  // a UUID child's FileName: the file holding these planes, "" for this one
};

struct OmePixels {
  int64_t size_x = 0, size_y = 0, size_z = 1, size_c = 1, size_t_ = 1;
  std::string dimension_order;             // "XYZCT", ...
  std::string type;                        // "uint16", "float", ...
  std::optional<double> physical_size[3];  // x, y, z, in physical_unit[a]
  std::string physical_unit[3] = {"µm", "µm", "µm"};
  bool big_endian = false;    // informational: libtiff reads the pages' own byte order
  int samples_per_pixel = 1;  // the largest Channel SamplesPerPixel
  int images = 0;             // Image elements in the document (only the first is read)
  std::vector<OmeTiffData> tiff_data;

  // Where plane (z, c, t) lies in DimensionOrder's sequence of planes.
  int64_t plane_index(int64_t z, int64_t c, int64_t t) const;
};

// Whether `description` is OME-XML (an <OME> root, possibly after an XML declaration).
bool is_ome_xml(std::string_view description);

// The first Image's Pixels. Throws imx::Error naming `what` and the attribute for XML that is
// malformed, larger than kMaxOmeXmlBytes, declares entities, or has sizes, an order or numbers
// that are missing or out of range.
OmePixels parse_ome_xml(std::string_view xml, const std::string& what);

}  // namespace imx::detail
