#include "io/tiff/tiff_file.hpp"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstring>

#include <fmt/format.h>
#include <tiffio.h>

#include "core/library_output.hpp"
#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streams/input_file.hpp"

namespace imx::detail {

namespace {

// The largest tile side read beyond the page's own (rounded up to TIFF's 16): a page of a few
// pixels may sit in one 256 x 256 tile, but a tile of 2^31 pixels is a bomb, not a layout.
constexpr uint32_t kMaxSpareTileSide = 1024;

// One formatted libtiff message.
std::string format_message(const char* module, const char* format, va_list args) {
  char text[1024];
  std::vsnprintf(text, sizeof text, format, args);
  std::string out = text;
  // libtiff's module is often the file name (or a function's): the caller names the file.
  if (module && *module && std::strchr(module, '/') == nullptr && out.find(module) != 0)
    out = std::string(module) + ": " + out;
  return out;
}

const char* photometric_name(int value) {
  switch (value) {
    case PHOTOMETRIC_MINISWHITE:
      return "MinIsWhite (inverted grey)";
    case PHOTOMETRIC_RGB:
      return "RGB";
    case PHOTOMETRIC_PALETTE:
      return "Palette (a colour map)";
    case PHOTOMETRIC_MASK:
      return "TransparencyMask";
    case PHOTOMETRIC_SEPARATED:
      return "Separated (CMYK)";
    case PHOTOMETRIC_YCBCR:
      return "YCbCr";
    case PHOTOMETRIC_CIELAB:
    case PHOTOMETRIC_ICCLAB:
    case PHOTOMETRIC_ITULAB:
      return "CIELab";
    default:
      return "an unknown kind";
  }
}

// The element type of BitsPerSample `bits` and SampleFormat `format`; "" or why not.
std::string sample_type(int bits, int format, RawType* type) {
  const char* formats[] = {"", "unsigned integer", "signed integer", "IEEE float"};
  if (format < 1 || format > 3)
    return fmt::format("SampleFormat {} (only unsigned, signed integers and IEEE floats are read)",
                       format);
  static constexpr RawType kTypes[4][3] = {{RawType::u8, RawType::i8, RawType::u8},
                                           {RawType::u16, RawType::i16, RawType::u16},
                                           {RawType::u32, RawType::i32, RawType::f32},
                                           {RawType::u64, RawType::i64, RawType::f64}};
  const int row = bits == 8 ? 0 : bits == 16 ? 1 : bits == 32 ? 2 : bits == 64 ? 3 : -1;
  if (row < 0 || (format == 3 && bits < 32))
    return fmt::format("BitsPerSample {} of {} (read are 8, 16, 32 and 64 bits; floats 32 and 64)",
                       bits, formats[format]);
  *type = kTypes[row][format - 1];
  return "";
}

}  // namespace

// libtiff's handle and where its messages go while this file is open.
struct TiffFile::Handle {
  TIFF* tif = nullptr;
  std::string error;  // libtiff's first error since the last take_error()
  std::string what;

  static int on_error(TIFF*, void* self, const char* module, const char* format, va_list args) {
    auto* h = static_cast<Handle*>(self);
    if (h->error.empty()) h->error = format_message(module, format, args);
    return 1;  // handled: nothing reaches libtiff's global handler (stderr)
  }
  static int on_warning(TIFF*, void* self, const char* module, const char* format, va_list args) {
    auto* h = static_cast<Handle*>(self);
    keep_library_output("libtiff", h->what, format_message(module, format, args));
    return 1;
  }
  std::string take_error() {
    std::string e = error.empty() ? std::string("libtiff gave no reason") : error;
    error.clear();
    return e;
  }
  ~Handle() {
    if (tif) TIFFClose(tif);
  }
};

TiffFile::TiffFile(const std::filesystem::path& file)
    : handle_(std::make_unique<Handle>()), what_(file.string()) {
  handle_->what = what_;
  InputFd fd = open_input(file, what_);  // libtiff reads the checked descriptor
  TIFFOpenOptions* options = TIFFOpenOptionsAlloc();
  TIFFOpenOptionsSetErrorHandlerExtR(options, &Handle::on_error, handle_.get());
  TIFFOpenOptionsSetWarningHandlerExtR(options, &Handle::on_warning, handle_.get());
  // No single allocation of libtiff's own (tag arrays, strip buffers) beyond the budget.
  TIFFOpenOptionsSetMaxSingleMemAlloc(
      options, static_cast<tmsize_t>(std::min<uint64_t>(input_limits().max_memory, INT64_MAX)));
  // "m": read, never map: a file truncated while mapped would end the process (SIGBUS).
  handle_->tif = TIFFFdOpenExt(fd.get(), what_.c_str(), "rm", options);
  TIFFOpenOptionsFree(options);
  if (handle_->tif) fd.release();  // TIFFClose closes it
  if (!handle_->tif)
    throw Error(fmt::format("{}: not a readable TIFF file: {}", what_, handle_->take_error()));
  for (int directory = 0;; ++directory) {
    pages_.push_back(describe_page(directory));
    if (!handle_->error.empty())
      throw Error(fmt::format("{}: page {}: {}", what_, directory, handle_->take_error()));
    if (!TIFFReadDirectory(handle_->tif)) break;
  }
  // TIFFReadDirectory says 0 both at the chain's end and for a corrupt next IFD.
  if (!handle_->error.empty())
    throw Error(fmt::format("{}: page {}: {}", what_, pages_.size(), handle_->take_error()));
}

TiffFile::~TiffFile() = default;

TiffPage TiffFile::describe_page(int directory) {
  TIFF* tif = handle_->tif;
  TiffPage p;
  p.directory = directory;
  p.offset = TIFFCurrentDirOffset(tif);
  uint32_t subfile = 0, depth = 1;
  uint16_t spp = 1, bits = 1, format = SAMPLEFORMAT_UINT, photometric = PHOTOMETRIC_MINISBLACK;
  uint16_t compression = COMPRESSION_NONE, unit = RESUNIT_INCH;
  float xres = 0, yres = 0;
  TIFFGetFieldDefaulted(tif, TIFFTAG_SUBFILETYPE, &subfile);
  p.reduced = (subfile & FILETYPE_REDUCEDIMAGE) != 0;
  TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &p.width);
  TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &p.height);
  TIFFGetFieldDefaulted(tif, TIFFTAG_IMAGEDEPTH, &depth);
  TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &spp);
  TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &bits);
  TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &format);
  TIFFGetFieldDefaulted(tif, TIFFTAG_COMPRESSION, &compression);
  if (!TIFFGetField(tif, TIFFTAG_PHOTOMETRIC, &photometric)) photometric = PHOTOMETRIC_MINISBLACK;
  if (TIFFGetField(tif, TIFFTAG_XRESOLUTION, &xres)) p.x_resolution = xres;
  if (TIFFGetField(tif, TIFFTAG_YRESOLUTION, &yres)) p.y_resolution = yres;
  TIFFGetFieldDefaulted(tif, TIFFTAG_RESOLUTIONUNIT, &unit);
  p.resolution_unit = unit;
  p.compression = compression;
  uint16_t sub_count = 0;
  uint64_t* sub_offsets = nullptr;
  if (TIFFGetField(tif, TIFFTAG_SUBIFD, &sub_count, &sub_offsets) && sub_count > 0)
    sub_ifds_ = true;
  if (directory == 0) {
    const char* text = nullptr;
    if (TIFFGetField(tif, TIFFTAG_IMAGEDESCRIPTION, &text) && text) description_ = text;
  }
  p.tiled = TIFFIsTiled(tif) != 0;
  if (p.tiled) {
    TIFFGetField(tif, TIFFTAG_TILEWIDTH, &p.tile_width);
    TIFFGetField(tif, TIFFTAG_TILELENGTH, &p.tile_height);
  } else {
    TIFFGetFieldDefaulted(tif, TIFFTAG_ROWSPERSTRIP, &p.rows_per_strip);
    p.rows_per_strip = std::min(p.rows_per_strip, p.height);
  }
  // Why this page cannot be a slice, first reason only.
  if (p.width == 0 || p.height == 0)
    p.problem = fmt::format("ImageWidth x ImageLength is {} x {}", p.width, p.height);
  else if (depth != 1)
    p.problem = fmt::format("ImageDepth {} (volumetric tiles are not read)", depth);
  else if (spp != 1)
    p.problem = fmt::format("SamplesPerPixel {} (only single-channel grey pages are read)", spp);
  else if (photometric != PHOTOMETRIC_MINISBLACK)
    p.problem = fmt::format("PhotometricInterpretation {} (only MinIsBlack grey is read)",
                            photometric_name(photometric));
  else if (std::string why = sample_type(bits, format, &p.type); !why.empty())
    p.problem = why;
  else if (!TIFFIsCODECConfigured(compression))
    p.problem = fmt::format("Compression {}, which this libtiff cannot decode", compression);
  else if (p.tiled && (p.tile_width == 0 || p.tile_height == 0 ||
                       p.tile_width > std::max(p.width + 15, kMaxSpareTileSide) ||
                       p.tile_height > std::max(p.height + 15, kMaxSpareTileSide)))
    p.problem = fmt::format("TileWidth x TileLength {} x {} for a {} x {} page", p.tile_width,
                            p.tile_height, p.width, p.height);
  else if (!p.tiled && p.rows_per_strip == 0)
    p.problem = "RowsPerStrip 0";
  return p;
}

void TiffFile::go_to(const TiffPage& page) {
  if (TIFFCurrentDirOffset(handle_->tif) == page.offset) return;
  if (!TIFFSetSubDirectory(handle_->tif, page.offset) || !handle_->error.empty())
    throw Error(fmt::format("{}: page {}: {}", what_, page.directory, handle_->take_error()));
  uint32_t width = 0, height = 0;
  TIFFGetField(handle_->tif, TIFFTAG_IMAGEWIDTH, &width);
  TIFFGetField(handle_->tif, TIFFTAG_IMAGELENGTH, &height);
  if (width != page.width || height != page.height)
    throw Error(fmt::format("{}: page {} changed while it was read", what_, page.directory));
}

void TiffFile::read_rows(const TiffPage& page, uint32_t y0, uint32_t y1, std::span<uint8_t> out) {
  if (!page.problem.empty())
    throw Error(fmt::format("{}: page {}: {}", what_, page.directory, page.problem));
  if (y0 >= y1 || y1 > page.height || out.size() != (y1 - y0) * page.row_bytes())
    throw Error(fmt::format("{}: page {}: rows {} to {} asked of {}", what_, page.directory, y0, y1,
                            page.height));
  go_to(page);
  if (page.tiled)
    read_tiles(page, y0, y1, out);
  else
    read_strips(page, y0, y1, out);
}

// libtiff reads an uncompressed strip's or tile's bytes from its offset whatever its byte count
// says: a count too small for its rows would take bytes the file gives to something else.
void TiffFile::check_stored_bytes(const TiffPage& page, uint32_t strile, uint64_t expected,
                                  const char* kind) {
  if (page.compression != COMPRESSION_NONE) return;
  const uint64_t stored = TIFFGetStrileByteCount(handle_->tif, strile);
  if (stored < expected)
    throw Error(fmt::format("{}: page {}: {} {}: {}ByteCounts gives {} bytes, its pixels need {}",
                            what_, page.directory, kind, strile, kind[0] == 's' ? "Strip" : "Tile",
                            stored, expected));
}

void TiffFile::read_strips(const TiffPage& page, uint32_t y0, uint32_t y1, std::span<uint8_t> out) {
  TIFF* tif = handle_->tif;
  const uint64_t row = page.row_bytes();
  const uint32_t rps = page.rows_per_strip;
  const uint32_t strips = TIFFNumberOfStrips(tif);
  std::vector<uint8_t> scratch;
  for (uint32_t s = y0 / rps; s <= (y1 - 1) / rps; ++s) {
    const uint32_t top = s * rps, rows = std::min(rps, page.height - top);
    const uint64_t expected = rows * row;
    if (s >= strips)
      throw Error(fmt::format("{}: page {}: strip {} missing (StripOffsets holds {})", what_,
                              page.directory, s, strips));
    check_stored_bytes(page, s, expected, "strip");
    // A strip inside the rows asked for is decoded in place; one across their ends aside.
    const bool inside = top >= y0 && top + rows <= y1;
    if (!inside) {
      check_memory(expected, fmt::format("{}: page {}: strip {}", what_, page.directory, s));
      scratch.resize(expected);
    }
    uint8_t* target = inside ? out.data() + (top - y0) * row : scratch.data();
    const tmsize_t got = TIFFReadEncodedStrip(tif, s, target, static_cast<tmsize_t>(expected));
    if (got < 0 || !handle_->error.empty())
      throw Error(fmt::format("{}: page {}: strip {}: {}", what_, page.directory, s,
                              handle_->take_error()));
    if (static_cast<uint64_t>(got) != expected)
      throw Error(fmt::format("{}: page {}: strip {} decodes to {} bytes, expected {}", what_,
                              page.directory, s, got, expected));
    if (!inside) {
      const uint32_t from = std::max(top, y0), to = std::min(top + rows, y1);
      std::memcpy(out.data() + (from - y0) * row, scratch.data() + (from - top) * row,
                  (to - from) * row);
    }
  }
}

void TiffFile::read_tiles(const TiffPage& page, uint32_t y0, uint32_t y1, std::span<uint8_t> out) {
  TIFF* tif = handle_->tif;
  const uint64_t element = raw_type_size(page.type), row = page.row_bytes();
  const uint64_t tile_row = uint64_t{page.tile_width} * element;
  const uint64_t expected = tile_row * page.tile_height;
  if (TIFFTileSize64(tif) != expected)
    throw Error(fmt::format("{}: page {}: tiles of {} bytes, expected {}", what_, page.directory,
                            TIFFTileSize64(tif), expected));
  check_memory(expected, fmt::format("{}: page {}: one tile", what_, page.directory));
  std::vector<uint8_t> tile(expected);
  const uint32_t tiles = TIFFNumberOfTiles(tif);
  for (uint32_t ty = y0 / page.tile_height * page.tile_height; ty < y1; ty += page.tile_height) {
    for (uint32_t tx = 0; tx < page.width; tx += page.tile_width) {
      const uint32_t t = TIFFComputeTile(tif, tx, ty, 0, 0);
      if (t >= tiles)
        throw Error(fmt::format("{}: page {}: tile {} missing (TileOffsets holds {})", what_,
                                page.directory, t, tiles));
      check_stored_bytes(page, t, expected, "tile");
      const tmsize_t got =
          TIFFReadEncodedTile(tif, t, tile.data(), static_cast<tmsize_t>(expected));
      if (got < 0 || !handle_->error.empty())
        throw Error(fmt::format("{}: page {}: tile {}: {}", what_, page.directory, t,
                                handle_->take_error()));
      if (static_cast<uint64_t>(got) != expected)
        throw Error(fmt::format("{}: page {}: tile {} decodes to {} bytes, expected {}", what_,
                                page.directory, t, got, expected));
      const uint32_t from = std::max(ty, y0), to = std::min({ty + page.tile_height, y1});
      const uint64_t width = std::min(page.tile_width, page.width - tx) * element;
      for (uint32_t y = from; y < to; ++y)
        std::memcpy(out.data() + (y - y0) * row + tx * element, tile.data() + (y - ty) * tile_row,
                    width);
    }
  }
}

}  // namespace imx::detail
