// One TIFF or BigTIFF file opened with libtiff: its pages (main-chain IFDs) described, and a
// page's rows decoded into a buffer of exactly their size. libtiff's messages never reach stderr:
// its errors become imx::Error naming the file and page.
#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "io/voxels/raw_voxels.hpp"

namespace imx::detail {

// One page (IFD of the main chain) as its tags describe it.
struct TiffPage {
  int directory = 0;    // its number in the main chain, counted from 0 (OME's "IFD")
  uint64_t offset = 0;  // where its IFD lies, to return to it
  uint32_t width = 0, height = 0;
  RawType type = RawType::u8;
  bool reduced = false;  // NewSubfileType bit 0: a reduced-resolution copy, never a slice
  bool tiled = false;
  uint32_t tile_width = 0, tile_height = 0;  // tiled pages
  uint32_t rows_per_strip = 0;               // striped pages (at most the height)
  int compression = 1;                       // TIFF's Compression: 1 none
  // Why the page cannot be a slice ("SamplesPerPixel 3 (colour)"), empty when it can: kept
  // rather than thrown, so that a page no slice uses (an RGB thumbnail) does no harm.
  std::string problem;
  // Resolution tags: pixels per unit (0 when absent), ResolutionUnit (1 none, 2 inch, 3 cm).
  double x_resolution = 0, y_resolution = 0;
  int resolution_unit = 2;

  uint64_t row_bytes() const { return uint64_t{width} * raw_type_size(type); }
  uint64_t bytes() const { return row_bytes() * height; }
};

class TiffFile {
 public:
  // Opens `file` and describes every page of its main chain. Throws imx::Error naming the file
  // when libtiff cannot open it or its IFD chain is corrupt.
  explicit TiffFile(const std::filesystem::path& file);
  ~TiffFile();
  TiffFile(const TiffFile&) = delete;
  TiffFile& operator=(const TiffFile&) = delete;

  const std::string& what() const { return what_; }
  const std::vector<TiffPage>& pages() const { return pages_; }
  // The first page's ImageDescription (OME-XML, ImageJ's key=value lines), "" when none.
  const std::string& description() const { return description_; }
  // Whether any page has SubIFDs (pyramid levels, which are not read).
  bool has_sub_ifds() const { return sub_ifds_; }

  // Rows [y0, y1) of `page` decoded into `out` (exactly (y1 - y0) * row_bytes() bytes), in the
  // host's byte order. Throws imx::Error naming the file, page and strip or tile when a strip or
  // tile is missing, corrupt, or decodes to another size.
  void read_rows(const TiffPage& page, uint32_t y0, uint32_t y1, std::span<uint8_t> out);

 private:
  struct Handle;
  std::unique_ptr<Handle> handle_;
  std::string what_;
  std::vector<TiffPage> pages_;
  std::string description_;
  bool sub_ifds_ = false;

  TiffPage describe_page(int directory);
  void go_to(const TiffPage& page);
  void read_strips(const TiffPage& page, uint32_t y0, uint32_t y1, std::span<uint8_t> out);
  void read_tiles(const TiffPage& page, uint32_t y0, uint32_t y1, std::span<uint8_t> out);
  void check_stored_bytes(const TiffPage& page, uint32_t strile, uint64_t expected,
                          const char* kind);
};

}  // namespace imx::detail
