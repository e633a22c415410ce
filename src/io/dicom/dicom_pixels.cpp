#include "io/dicom/dicom_pixels.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <span>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <limits>

#include <fmt/format.h>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include "core/isolated_call.hpp"
#include "core/library_output.hpp"
#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/dicom/dicom_codec_plugin.hpp"
#include "io/dicom/dicom_tags.hpp"
#include "io/streams/input_file.hpp"
#include "volume/colour_grid.hpp"

namespace imx::detail {

namespace {

using Stored = StoredType;

}  // namespace

size_t stored_size(Stored t) {
  switch (t) {
    case Stored::u8:
    case Stored::i8:
      return 1;
    case Stored::u16:
    case Stored::i16:
      return 2;
    case Stored::u32:
    case Stored::i32:
    case Stored::f32:
      return 4;
    default:
      return 8;
  }
}

namespace {

// Undecoded or decoded pixel values in host order, as stored (before rescale).
struct RawPixels {
  const char* data = nullptr;
  Stored type = Stored::u16;
  int bits_stored = 16, high_bit = 15;
};

template <class T>
void rescale_integers(const RawPixels& raw, size_t base, size_t plane, const DicomFrame& meta,
                      float* dst) {
  constexpr int allocated = static_cast<int>(sizeof(T) * 8);
  int shift = 0, used = allocated;
  if (raw.bits_stored > 0 && raw.bits_stored < allocated && raw.high_bit >= raw.bits_stored - 1 &&
      raw.high_bit < allocated) {
    shift = raw.high_bit + 1 - raw.bits_stored;
    used = raw.bits_stored;
  }
  // The bits outside BitsStored (overlays, or a sign extension) give way to the stored value's
  // sign: the used bits go to the top of a 32-bit lane (64 for 32-bit pixels), then back down
  // with the sign or zeros. No branch, so the loop vectorizes.
  using Unsigned = std::conditional_t<(sizeof(T) <= 2), uint32_t, uint64_t>;
  using Signed = std::make_signed_t<Unsigned>;
  constexpr int wide = static_cast<int>(sizeof(Unsigned) * 8);
  const int up = wide - used;
  const char* src = raw.data + base * sizeof(T);
  for (size_t i = 0; i < plane; ++i) {
    T stored;
    std::memcpy(&stored, src + i * sizeof(T), sizeof(T));
    const Unsigned u = static_cast<Unsigned>(static_cast<std::make_unsigned_t<T>>(stored) >> shift)
                       << up;
    const double v = std::is_signed_v<T> ? static_cast<double>(static_cast<Signed>(u) >> up)
                                         : static_cast<double>(u >> up);
    dst[i] = static_cast<float>(v * meta.slope + meta.intercept);
  }
}

template <class T>
void rescale_floats(const RawPixels& raw, size_t base, size_t plane, const DicomFrame& meta,
                    float* dst) {
  for (size_t i = 0; i < plane; ++i) {
    T v;
    std::memcpy(&v, raw.data + (base + i) * sizeof(T), sizeof(T));
    dst[i] = static_cast<float>(static_cast<double>(v) * meta.slope + meta.intercept);
  }
}

std::optional<Stored> integer_type(int bits_allocated, bool is_signed) {
  switch (bits_allocated) {
    case 8:
      return is_signed ? Stored::i8 : Stored::u8;
    case 16:
      return is_signed ? Stored::i16 : Stored::u16;
    case 32:
      return is_signed ? Stored::i32 : Stored::u32;
    default:
      return std::nullopt;
  }
}

// Reused per thread: a fresh buffer of a slice's size is a fresh mapping, faulted in page by page.
std::vector<char>& scratch_buffer() {
  thread_local std::vector<char> buffer;
  return buffer;
}

// Native little-endian data is read straight from the file (as dcm2niix does): GDCM would parse
// the whole file again and copy the pixels twice.
bool read_native(const DicomFileHeader& h, size_t count, RawPixels& raw) {
  const std::string& ts = h.transfer_syntax;
  if (ts != "1.2.840.10008.1.2" && ts != "1.2.840.10008.1.2.1") return false;
  if (h.samples_per_pixel != 1) return false;
  std::optional<Stored> type = integer_type(h.bits_allocated, h.pixel_representation == 1);
  if (!type) return false;
  const uint64_t bytes = count * stored_size(*type);
  if (h.pixel_bytes < bytes) return false;  // reported as truncated by the caller
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(h.file, ec);
  if (ec || size < h.pixel_bytes) return false;
  std::ifstream in = try_open_input_stream(h.file);
  in.seekg(static_cast<std::streamoff>(size - h.pixel_bytes));
  std::vector<char>& buffer = scratch_buffer();
  buffer.resize(bytes);
  in.read(buffer.data(), static_cast<std::streamsize>(bytes));
  if (in.gcount() != static_cast<std::streamsize>(bytes)) return false;
  raw.data = buffer.data();
  raw.type = *type;
  raw.bits_stored = h.bits_stored;
  raw.high_bit = h.high_bit;
  return true;
}

// What a decoder process reports before each file's pixels in the memory it shares.
struct DecodedFormat {
  Stored type = Stored::u16;
  int bits_stored = 0, high_bit = 0;
};

size_t pixel_count(const DicomFileHeader& h) {
  return static_cast<size_t>(h.stored_rows) * h.stored_columns *
         static_cast<size_t>(h.stored_frames);
}

// Room for one file's decoded pixels: GDCM decodes to BitsAllocated per value.
size_t decoded_room(const DicomFileHeader& h) {
  return sizeof(DecodedFormat) +
         pixel_count(h) * static_cast<size_t>(std::max(h.bits_allocated, 8) / 8);
}

std::optional<Stored> stored_type_of(int32_t scalar) {
  switch (scalar) {
    case IMX_DICOM_CODEC_U8:
      return Stored::u8;
    case IMX_DICOM_CODEC_I8:
      return Stored::i8;
    case IMX_DICOM_CODEC_U16:
      return Stored::u16;
    case IMX_DICOM_CODEC_I16:
      return Stored::i16;
    case IMX_DICOM_CODEC_U32:
      return Stored::u32;
    case IMX_DICOM_CODEC_I32:
      return Stored::i32;
    case IMX_DICOM_CODEC_F32:
      return Stored::f32;
    case IMX_DICOM_CODEC_F64:
      return Stored::f64;
    default:
      return std::nullopt;
  }
}

// Decodes one file with the codec plugin into `out` (a DecodedFormat, then the pixels); throws
// imx::Error.
void decode_with_plugin(imx_dicom_codec_decode_fn decode, const DicomFileHeader& header,
                        std::span<std::byte> out) {
  const std::string what = header.file.string();
  imx_dicom_codec_format decoded{};
  char message[512];
  const InputFd fd = open_input(header.file, what);  // GDCM opens the checked file by this name
  const int32_t status =
      decode(path_of_open(fd, header.file).c_str(), static_cast<uint32_t>(header.stored_columns),
             static_cast<uint32_t>(header.stored_rows), static_cast<uint32_t>(header.stored_frames),
             out.data() + sizeof(DecodedFormat), out.size() - sizeof(DecodedFormat), &decoded,
             message, sizeof message);
  message[sizeof message - 1] = '\0';
  if (status == IMX_DICOM_CODEC_CORRUPT)
    throw Error(fmt::format("{}: cannot decode the pixel data (transfer syntax {}): corrupt", what,
                            transfer_syntax_label(header.transfer_syntax)));
  if (status != IMX_DICOM_CODEC_OK) throw Error(fmt::format("{}: {}", what, message));
  const std::optional<Stored> type = stored_type_of(decoded.scalar);
  if (!type)
    throw Error(fmt::format("{}: the DICOM codec plugin gave an unknown pixel type {}", what,
                            decoded.scalar));
  DecodedFormat format;
  format.type = *type;
  format.bits_stored = decoded.bits_stored;
  format.high_bit = decoded.high_bit;
  std::memcpy(out.data(), &format, sizeof format);
}

// Words in a decoder's own messages that mean it met corrupt data, although it went on (libjpeg
// warns "Corrupt JPEG data: ..." and "Premature end of JPEG file", and fills in grey).
bool reports_corruption(const std::string& output) {
  std::string low = output;
  std::transform(low.begin(), low.end(), low.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* word : {"corrupt", "premature end", "error", "invalid", "truncat"})
    if (low.find(word) != std::string::npos) return true;
  return false;
}

// The files of one child process: decoded one after another into one shared mapping.
CodecPixels take_decoded(std::span<const std::byte> room) {
  DecodedFormat format;
  std::memcpy(&format, room.data(), sizeof format);
  CodecPixels out;
  out.type = format.type;
  out.bits_stored = format.bits_stored;
  out.high_bit = format.high_bit;
  out.bytes.resize(room.size() - sizeof format);
  std::memcpy(out.bytes.data(), room.data() + sizeof format, out.bytes.size());
  return out;
}

void decode_batch(imx_dicom_codec_decode_fn decode, std::span<const DicomFileHeader* const> files,
                  std::span<CodecPixels> out) {
  // The first bytes say which file the child is decoding, so that a crash can name it.
  constexpr size_t kIndexBytes = 64;
  std::vector<size_t> offsets{kIndexBytes};
  for (const DicomFileHeader* h : files) offsets.push_back(offsets.back() + decoded_room(*h));
  size_t dying = 0;
  double seconds = 120.0;
  for (const DicomFileHeader* h : files)
    seconds += static_cast<double>(decoded_room(*h)) / (4 << 20);
  // The codecs' working memory beside the pixels Rows x Columns x frames say: a few times them
  // and a margin, within the budget. A stream that decodes to more is corrupt (a 175-byte
  // JPEG once asked for 23 GB).
  const uint64_t memory_limit =
      std::min<uint64_t>(input_limits().max_memory, (uint64_t{256} << 20) + 8 * offsets.back());
  const IsolatedResult r = run_isolated(
      offsets.back(),
      [&](std::span<std::byte> shared) {
        for (size_t i = 0; i < files.size(); ++i) {
          std::memcpy(shared.data(), &i, sizeof i);
          decode_with_plugin(decode, *files[i],
                             shared.subspan(offsets[i], offsets[i + 1] - offsets[i]));
        }
      },
      seconds,
      [&](std::span<const std::byte> shared) {
        std::memcpy(&dying, shared.data(), sizeof dying);
        for (size_t i = 0; i < files.size(); ++i) {
          DecodedFormat format;
          std::memcpy(&format, shared.data() + offsets[i], sizeof format);
          const size_t bytes = pixel_count(*files[i]) * stored_size(format.type);
          out[i] = take_decoded(shared.subspan(offsets[i], sizeof format + bytes));
        }
      },
      memory_limit);
  // The failing file: the child names it in its error; a crash names the one it was decoding.
  const DicomFileHeader& failed = *files[std::min(dying, files.size() - 1)];
  const std::string what = failed.file.string();
  const std::string syntax = "transfer syntax " + transfer_syntax_label(failed.transfer_syntax);
  if (!r.output.empty())
    keep_library_output("decoder", files.size() == 1 ? what : "a series", r.output);
  switch (r.end) {
    case IsolatedResult::End::failed:
      throw Error(r.error);
    case IsolatedResult::End::crashed:
      throw Error(
          fmt::format("{}: the pixel data decoder failed ({}) on this file's {}: corrupt "
                      "compressed data",
                      what, r.detail, syntax));
    case IsolatedResult::End::timed_out:
      throw Error(fmt::format("{}: the pixel data decoder did not finish in {:.0f} s ({})", what,
                              seconds, syntax));
    case IsolatedResult::End::over_memory:
      throw Error(fmt::format(
          "{}: the pixel data decoder needed more than {} for this file's {}: corrupt compressed "
          "data",
          what, format_bytes(memory_limit), syntax));
    case IsolatedResult::End::finished:
      break;
  }
  if (reports_corruption(r.output)) {
    // Which file the codec complained of is not known in a batch of several: decode those alone.
    if (files.size() > 1) {
      for (size_t i = 0; i < files.size(); ++i)
        decode_batch(decode, files.subspan(i, 1), out.subspan(i, 1));
      return;
    }
    const std::string first = r.output.substr(0, r.output.find('\n'));
    throw Error(
        fmt::format("{}: the decoder reports corrupt pixel data ({}): {}", what, syntax, first));
  }
}

// The tiles of a mosaic, row by row from its top left, as many as it holds images.
std::vector<FloatPlane> split_mosaic(const FloatPlane& mosaic, const DicomFileHeader& h) {
  const int per_row = h.stored_columns / h.columns;
  std::vector<FloatPlane> tiles(static_cast<size_t>(h.mosaic_tiles));
  for (int t = 0; t < h.mosaic_tiles; ++t) {
    FloatPlane& tile = tiles[static_cast<size_t>(t)];
    tile.resize(static_cast<size_t>(h.rows) * h.columns);
    const size_t x0 = static_cast<size_t>(t % per_row) * h.columns;
    const size_t y0 = static_cast<size_t>(t / per_row) * h.rows;
    for (int y = 0; y < h.rows; ++y)
      std::copy_n(mosaic.data() + (y0 + y) * h.stored_columns + x0, h.columns,
                  tile.data() + static_cast<size_t>(y) * h.columns);
  }
  return tiles;
}

// Refuses what cannot be decoded into greyscale values before any decoder sees it (GDCM asserts
// on some of these rather than failing).
void check_decodable(const DicomFileHeader& header) {
  const std::string what = header.file.string();
  if (!header.has_pixel_data)
    throw Error(fmt::format("{}: no pixel data (7FE0,0010) in this file", what));
  const bool rgb = header.photometric == "RGB";
  if (!rgb && header.photometric != "MONOCHROME1" && header.photometric != "MONOCHROME2")
    throw Error(fmt::format(
        "{}: unsupported photometric interpretation '{}' (0028,0004): only greyscale "
        "MONOCHROME1 and MONOCHROME2 and colour RGB images are read{}",
        what, header.photometric,
        header.photometric.rfind("YBR", 0) == 0
            ? " (YBR colour is not converted; convert the series to RGB first, e.g. gdcmconv "
              "--raw --photometric-interpretation RGB)"
            : ""));
  if (rgb && !is_rgb_image(header))
    throw Error(fmt::format(
        "{}: unsupported RGB image: SamplesPerPixel {} (0028,0002), BitsAllocated {}, "
        "BitsStored {}, PixelRepresentation {}, transfer syntax {}{}; RGB is read as 3 unsigned "
        "8-bit samples per pixel, uncompressed",
        what, header.samples_per_pixel, header.bits_allocated, header.bits_stored,
        header.pixel_representation, header.transfer_syntax,
        header.mosaic_tiles > 0 ? ", a mosaic" : ""));
  // The decoded values (up to 8 bytes each) and the floats made of them.
  check_memory(pixel_count(header) * 12,
               fmt::format("{} ({}x{}x{} pixels)", what, header.stored_columns, header.stored_rows,
                           header.stored_frames));
  if (!rgb && header.samples_per_pixel != 1)
    throw Error(
        fmt::format("{}: unsupported photometric interpretation: {} samples per pixel "
                    "(SamplesPerPixel (0028,0002)); only greyscale images are read",
                    what, header.samples_per_pixel));
  const int ba = header.bits_allocated;
  if ((ba != 8 && ba != 16 && ba != 32 && ba != 64) || header.bits_stored < 1 ||
      header.bits_stored > ba || header.high_bit < header.bits_stored - 1 ||
      header.high_bit >= ba || header.pixel_representation > 1)
    throw Error(
        fmt::format("{}: unsupported pixel format: BitsAllocated {}, BitsStored {}, "
                    "HighBit {}, PixelRepresentation {}",
                    what, ba, header.bits_stored, header.high_bit, header.pixel_representation));
}

}  // namespace

bool is_rgb_image(const DicomFileHeader& h) {
  const std::string& ts = h.transfer_syntax;
  return h.photometric == "RGB" && h.samples_per_pixel == 3 && h.bits_allocated == 8 &&
         h.bits_stored == 8 && h.pixel_representation == 0 && h.mosaic_tiles == 0 &&
         (h.planar_configuration == 0 || h.planar_configuration == 1) &&
         (ts == "1.2.840.10008.1.2" || ts == "1.2.840.10008.1.2.1");
}

bool needs_codec(const DicomFileHeader& h) {
  const std::string& ts = h.transfer_syntax;
  if (is_rgb_image(h)) return false;  // read natively (decode_rgb_frames)
  return (ts != "1.2.840.10008.1.2" && ts != "1.2.840.10008.1.2.1") || h.samples_per_pixel != 1 ||
         !integer_type(h.bits_allocated, h.pixel_representation == 1);
}

std::vector<CodecPixels> decode_with_codecs(std::span<const DicomFileHeader* const> headers) {
  quiet_gdcm();
  for (const DicomFileHeader* h : headers) check_decodable(*h);
  std::vector<CodecPixels> out(headers.size());
  if (headers.empty()) return out;
  // Loaded here, before the decoder processes fork, so that each inherits it.
  const imx_dicom_codec_decode_fn decode = dicom_codec(headers.front()->file.string());
  // One child process per worker thread, each decoding its share in turn: a fork costs more the
  // more memory this process holds (40 ms at 1 GiB), so not one per file.
  const size_t children = std::min(
      headers.size(), static_cast<size_t>(std::max(1, tbb::this_task_arena::max_concurrency())));
  tbb::parallel_for(size_t{0}, children, [&](size_t c) {
    const size_t begin = headers.size() * c / children, end = headers.size() * (c + 1) / children;
    decode_batch(decode, headers.subspan(begin, end - begin),
                 std::span<CodecPixels>(out).subspan(begin, end - begin));
  });
  return out;
}

std::vector<std::string> codec_failures(std::span<const DicomFileHeader* const> headers) {
  std::vector<const DicomFileHeader*> coded;
  std::vector<std::string> out;
  for (const DicomFileHeader* h : headers) {
    if (needs_codec(*h)) {
      coded.push_back(h);
      continue;
    }
    // Native files too are refused by their header (no pixel data, an unsupported format).
    try {
      check_decodable(*h);
    } catch (const Error& e) {
      out.push_back(e.what());
    }
  }
  // A chunk's pixels are dropped before the next, so a large folder never sits in memory whole.
  constexpr size_t kChunk = 64;
  for (size_t begin = 0; begin < coded.size(); begin += kChunk) {
    const auto chunk = std::span(coded).subspan(begin, std::min(kChunk, coded.size() - begin));
    try {
      decode_with_codecs(chunk);
      continue;
    } catch (const Error&) {
    }
    // Something in the chunk failed: only each file alone can say which, and why.
    for (const DicomFileHeader* h : chunk) try {
        decode_with_codecs(std::span(&h, 1));
      } catch (const Error& e) {
        out.push_back(e.what());
      }
  }
  return out;
}

namespace {

// The frames of an RGB file (is_rgb_image): each frame's colours, interleaved whichever
// PlanarConfiguration stored them, and their luminance (colour_luminance) as its values.
DecodedFrames decode_rgb_frames(const DicomFileHeader& header) {
  const std::string what = header.file.string();
  const size_t plane = static_cast<size_t>(header.stored_rows) * header.stored_columns;
  const uint64_t bytes = 3 * plane * static_cast<uint64_t>(header.stored_frames);
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(header.file, ec);
  if (ec || header.pixel_bytes < bytes || size < header.pixel_bytes)
    throw Error(fmt::format("{}: the pixel data holds {} bytes, {} RGB frames of {}x{} need {}",
                            what, header.pixel_bytes, header.stored_frames, header.stored_columns,
                            header.stored_rows, bytes));
  std::ifstream in = open_input_stream(header.file, what);
  in.seekg(static_cast<std::streamoff>(size - header.pixel_bytes));
  std::vector<uint8_t> stored(bytes);
  in.read(reinterpret_cast<char*>(stored.data()), static_cast<std::streamsize>(bytes));
  if (in.gcount() != static_cast<std::streamsize>(bytes))
    throw Error(fmt::format("{}: the pixel data ends before its {} bytes", what, bytes));
  DecodedFrames out;
  out.frames.resize(static_cast<size_t>(header.stored_frames));
  out.colours.resize(out.frames.size());
  const bool by_plane = header.planar_configuration == 1;
  for (size_t f = 0; f < out.frames.size(); ++f) {
    const uint8_t* src = stored.data() + f * 3 * plane;
    std::vector<uint8_t>& rgb = out.colours[f];
    FloatPlane& values = out.frames[f];
    rgb.resize(3 * plane);
    values.resize(plane);
    for (size_t i = 0; i < plane; ++i) {
      for (size_t c = 0; c < 3; ++c)
        rgb[3 * i + c] = by_plane ? src[c * plane + i] : src[3 * i + c];
      values[i] = colour_luminance(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
    }
    if (header.mirror_rows)
      for (int y = 0; y < header.rows / 2; ++y) {
        const size_t a = static_cast<size_t>(y) * header.columns;
        const size_t b = static_cast<size_t>(header.rows - 1 - y) * header.columns;
        std::swap_ranges(values.begin() + a, values.begin() + a + header.columns,
                         values.begin() + b);
        std::swap_ranges(rgb.begin() + 3 * a, rgb.begin() + 3 * (a + header.columns),
                         rgb.begin() + 3 * b);
      }
  }
  return out;
}

}  // namespace

DecodedFrames decode_dicom_frames(const DicomFileHeader& header, const CodecPixels* codec) {
  check_decodable(header);
  if (is_rgb_image(header)) return decode_rgb_frames(header);
  const std::string what = header.file.string();
  const size_t plane = static_cast<size_t>(header.stored_rows) * header.stored_columns;
  const size_t count = pixel_count(header);
  RawPixels raw;
  CodecPixels own;
  if (codec == nullptr && !read_native(header, count, raw)) {
    const DicomFileHeader* one = &header;
    own = std::move(decode_with_codecs(std::span(&one, 1)).front());
    codec = &own;
  }
  if (codec != nullptr) {
    raw.data = codec->bytes.data();
    raw.type = codec->type;
    raw.bits_stored = codec->bits_stored;
    raw.high_bit = codec->high_bit;
  }
  const bool floats = raw.type == Stored::f32 || raw.type == Stored::f64;
  DecodedFrames out;
  out.integer_pixels = !floats;
  out.frames.resize(static_cast<size_t>(header.stored_frames));
  for (size_t f = 0; f < out.frames.size(); ++f) {
    const DicomFrame& meta = header.frames[f];
    FloatPlane& dst = out.frames[f];
    dst.resize(plane);
    const size_t base = f * plane;
    switch (raw.type) {
      case Stored::u8:
        rescale_integers<uint8_t>(raw, base, plane, meta, dst.data());
        break;
      case Stored::i8:
        rescale_integers<int8_t>(raw, base, plane, meta, dst.data());
        break;
      case Stored::u16:
        rescale_integers<uint16_t>(raw, base, plane, meta, dst.data());
        break;
      case Stored::i16:
        rescale_integers<int16_t>(raw, base, plane, meta, dst.data());
        break;
      case Stored::u32:
        rescale_integers<uint32_t>(raw, base, plane, meta, dst.data());
        break;
      case Stored::i32:
        rescale_integers<int32_t>(raw, base, plane, meta, dst.data());
        break;
      case Stored::f32:
        rescale_floats<float>(raw, base, plane, meta, dst.data());
        break;
      case Stored::f64:
        rescale_floats<double>(raw, base, plane, meta, dst.data());
        break;
    }
    // Integers times a modest slope stay finite; anything else is checked.
    if (floats || !(std::abs(meta.slope) < 1e20 && std::abs(meta.intercept) < 1e30))
      for (float v : dst)
        if (!std::isfinite(v))
          throw Error(
              fmt::format("{}: frame {} holds a value that is not finite after rescale "
                          "(slope {}, intercept {})",
                          what, f + 1, meta.slope, meta.intercept));
  }
  std::vector<char>& buffer = scratch_buffer();
  if (buffer.capacity() > (size_t{64} << 20)) std::vector<char>().swap(buffer);  // keep small ones
  if (header.mosaic_tiles > 0) out.frames = split_mosaic(out.frames.front(), header);
  if (header.mirror_rows)
    for (FloatPlane& f : out.frames)
      for (int y = 0; y < header.rows / 2; ++y)
        std::swap_ranges(
            f.begin() + static_cast<std::ptrdiff_t>(y) * header.columns,
            f.begin() + static_cast<std::ptrdiff_t>(y + 1) * header.columns,
            f.begin() + static_cast<std::ptrdiff_t>(header.rows - 1 - y) * header.columns);
  return out;
}

namespace {

// Reduces stored values to their BitsStored in place, as rescale_integers reads them (the bits
// outside give way to the value's sign), and returns their range.
template <class T>
StoredRange reduce_to_bits_stored(std::byte* bytes, size_t count, int bits_stored, int high_bit) {
  constexpr int allocated = static_cast<int>(sizeof(T) * 8);
  int shift = 0, used = allocated;
  if (bits_stored > 0 && bits_stored < allocated && high_bit >= bits_stored - 1 &&
      high_bit < allocated) {
    shift = high_bit + 1 - bits_stored;
    used = bits_stored;
  }
  T* values = reinterpret_cast<T*>(bytes);
  T lo = std::numeric_limits<T>::max(), hi = std::numeric_limits<T>::lowest();
  if (used == allocated) {
    for (size_t i = 0; i < count; ++i) {
      lo = std::min(lo, values[i]);
      hi = std::max(hi, values[i]);
    }
    return {lo, hi};
  }
  using Unsigned = std::conditional_t<(sizeof(T) <= 2), uint32_t, uint64_t>;
  using Signed = std::make_signed_t<Unsigned>;
  constexpr int wide = static_cast<int>(sizeof(Unsigned) * 8);
  const int up = wide - used;
  for (size_t i = 0; i < count; ++i) {
    const Unsigned u =
        static_cast<Unsigned>(static_cast<std::make_unsigned_t<T>>(values[i]) >> shift) << up;
    const T v = std::is_signed_v<T> ? static_cast<T>(static_cast<Signed>(u) >> up)
                                    : static_cast<T>(u >> up);
    values[i] = v;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  return {lo, hi};
}

StoredRange reduce_to_bits_stored(Stored type, std::byte* bytes, size_t count, int bits_stored,
                                  int high_bit) {
  switch (type) {
    case Stored::u8:
      return reduce_to_bits_stored<uint8_t>(bytes, count, bits_stored, high_bit);
    case Stored::i8:
      return reduce_to_bits_stored<int8_t>(bytes, count, bits_stored, high_bit);
    case Stored::u16:
      return reduce_to_bits_stored<uint16_t>(bytes, count, bits_stored, high_bit);
    case Stored::i16:
      return reduce_to_bits_stored<int16_t>(bytes, count, bits_stored, high_bit);
    case Stored::u32:
      return reduce_to_bits_stored<uint32_t>(bytes, count, bits_stored, high_bit);
    case Stored::i32:
      return reduce_to_bits_stored<int32_t>(bytes, count, bits_stored, high_bit);
    default:
      return {};  // native_stored_type gives integers only
  }
}

// A file's pixel data, where read_native finds it: pixel_bytes before the end of the file as it
// is now.
class PixelFile {
 public:
  explicit PixelFile(const DicomFileHeader& h) : fd_(open_fd(h.file)) {
    struct stat st {};
    ok_ = fd_ >= 0 && ::fstat(fd_, &st) == 0 && st.st_size >= 0 &&
          static_cast<uint64_t>(st.st_size) >= h.pixel_bytes;
    if (ok_) at_ = static_cast<off_t>(static_cast<uint64_t>(st.st_size) - h.pixel_bytes);
  }
  ~PixelFile() {
    if (fd_ >= 0) ::close(fd_);
  }
  PixelFile(const PixelFile&) = delete;
  // The guarded open's descriptor, -1 when it refuses the file (read_native then says why).
  static int open_fd(const std::filesystem::path& file) {
    try {
      return open_input(file).release();
    } catch (const Error&) {
      return -1;
    }
  }
  PixelFile& operator=(const PixelFile&) = delete;

  // Bytes [from, from + bytes) of the pixel data into dst, in pieces of `piece` bytes, each
  // handed to `on_piece` (offset in dst, length) while it is still in the cache.
  template <class F>
  bool read(size_t from, std::byte* dst, size_t bytes, size_t piece, F&& on_piece) {
    for (size_t begin = 0; ok_ && begin < bytes; begin += piece) {
      const size_t end = std::min(bytes, begin + piece);
      for (size_t done = begin; ok_ && done < end;) {
        const ssize_t n =
            ::pread(fd_, dst + done, end - done, at_ + static_cast<off_t>(from + done));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0)
          ok_ = false;
        else
          done += static_cast<size_t>(n);
      }
      if (ok_) on_piece(begin, end - begin);
    }
    return ok_;
  }

 private:
  int fd_;
  bool ok_ = false;
  off_t at_ = 0;
};

// GE's reversed-polarity rows put back, as decode_dicom_frames does.
void mirror_rows(const DicomFileHeader& h, std::byte* image, size_t row_bytes) {
  if (!h.mirror_rows) return;
  for (int y = 0; y < h.rows / 2; ++y)
    std::swap_ranges(image + static_cast<size_t>(y) * row_bytes,
                     image + static_cast<size_t>(y + 1) * row_bytes,
                     image + static_cast<size_t>(h.rows - 1 - y) * row_bytes);
}

}  // namespace

std::optional<StoredType> native_stored_type(const DicomFileHeader& header) {
  if (needs_codec(header) || is_rgb_image(header)) return std::nullopt;  // RGB: decoded frames
  try {
    check_decodable(header);
  } catch (const std::exception&) {
    return std::nullopt;  // decode_dicom_frames refuses it in its own words
  }
  return integer_type(header.bits_allocated, header.pixel_representation == 1);
}

bool read_stored_images(const DicomFileHeader& h, std::span<std::byte* const> images,
                        std::span<StoredRange> ranges) {
  const std::optional<Stored> type = native_stored_type(h);
  if (!type || images.size() != static_cast<size_t>(h.frame_count) ||
      ranges.size() != images.size())
    return false;
  const size_t size = stored_size(*type);
  const size_t bytes = pixel_count(h) * size;
  if (h.pixel_bytes < bytes) return false;
  const size_t image = static_cast<size_t>(h.rows) * h.columns;
  const size_t row_bytes = static_cast<size_t>(h.columns) * size;
  PixelFile file(h);
  if (h.mosaic_tiles == 0) {
    // Each frame straight to its place, and its range taken piece by piece while the piece is
    // in the cache (a second pass over the frame would fetch it from memory again).
    constexpr size_t kPiece = size_t{64} << 10;
    for (size_t i = 0; i < images.size(); ++i) {
      std::byte* dst = images[i];
      if (dst == nullptr) continue;
      StoredRange range{std::numeric_limits<int64_t>::max(), std::numeric_limits<int64_t>::min()};
      if (!file.read(i * image * size, dst, image * size, kPiece, [&](size_t at, size_t length) {
            const StoredRange r =
                reduce_to_bits_stored(*type, dst + at, length / size, h.bits_stored, h.high_bit);
            range = {std::min(range.lo, r.lo), std::max(range.hi, r.hi)};
          }))
        return false;
      ranges[i] = range;
      mirror_rows(h, dst, row_bytes);
    }
    return true;
  }
  // A mosaic through this thread's buffer, tile by tile.
  std::vector<char>& buffer = scratch_buffer();
  buffer.resize(bytes);
  std::byte* data = reinterpret_cast<std::byte*>(buffer.data());
  if (!file.read(0, data, bytes, bytes, [](size_t, size_t) {})) return false;
  const int per_row = h.stored_columns / h.columns;
  for (size_t i = 0; i < images.size(); ++i) {
    std::byte* dst = images[i];
    if (dst == nullptr) continue;
    const size_t x0 = static_cast<size_t>(static_cast<int>(i) % per_row) * h.columns;
    const size_t y0 = static_cast<size_t>(static_cast<int>(i) / per_row) * h.rows;
    for (int y = 0; y < h.rows; ++y)
      std::memcpy(dst + static_cast<size_t>(y) * row_bytes,
                  data + ((y0 + y) * h.stored_columns + x0) * size, row_bytes);
    ranges[i] = reduce_to_bits_stored(*type, dst, image, h.bits_stored, h.high_bit);
    mirror_rows(h, dst, row_bytes);
  }
  if (buffer.capacity() > (size_t{64} << 20)) std::vector<char>().swap(buffer);  // keep small ones
  return true;
}

}  // namespace imx::detail
