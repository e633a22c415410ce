// Decoding one DICOM file's pixels through GDCM (every transfer syntax it supports) into
// rescaled values, one float plane per frame.
#pragma once
#include <cstdint>
#include <memory>
#include <new>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "io/dicom/dicom_header.hpp"

namespace imx::detail {

// Leaves values default-initialized (floats uninitialized) when a vector is sized: a plane is
// written whole right after, and zeroing it first was a third of the time to read a CT series.
template <class T>
struct UninitializedAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() = default;
  template <class U>
  UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

// One frame's rescaled values, rows * columns, x fastest.
using FloatPlane = std::vector<float, UninitializedAllocator<float>>;

struct DecodedFrames {
  std::vector<FloatPlane> frames;  // one per frame
  bool integer_pixels = true;      // stored values are integers (not float pixel data)
  // An RGB image's colours, one per frame: rows * columns * 3 bytes, r g b interleaved; `frames`
  // then hold their luminance (colour_grid.hpp). Empty for a greyscale image.
  std::vector<std::vector<uint8_t>> colours;
};

// Whether a file's images are colour ones intermix reads: PhotometricInterpretation RGB, three
// 8-bit unsigned samples per pixel, native (uncompressed) little endian.
bool is_rgb_image(const DicomFileHeader& header);

enum class StoredType : uint8_t { u8, i8, u16, i16, u32, i32, f32, f64 };

// One file's pixel values as stored (before rescale), from GDCM's codecs.
struct CodecPixels {
  std::vector<char> bytes;
  StoredType type = StoredType::u16;
  int bits_stored = 0, high_bit = 0;
};

// True when a file's pixels need GDCM's codecs: every transfer syntax but native little endian
// (RLE, JPEG, JPEG-LS, JPEG 2000, big endian, deflate), and unusual pixel formats.
bool needs_codec(const DicomFileHeader& header);

// Decodes the pixel data of files that need codecs in child processes (one per worker thread,
// each taking its share of the files in turn), so that a codec that aborts or faults on corrupt
// data is an error naming the file, not the end of the program. A codec that reports corruption
// is an error too; what codecs print is kept for --verbose (core/library_output.hpp). Throws
// imx::Error naming the first file that fails.
std::vector<CodecPixels> decode_with_codecs(std::span<const DicomFileHeader* const> headers);

// Decodes the files that need codecs as decode_with_codecs does, a few at a time, keeping no
// pixels: one message per file that cannot be decoded (what reading it would throw; a native
// file's header checks too, such as no pixel data); empty when every file decodes. What `info`
// checks so that it lists each file `convert` would refuse.
std::vector<std::string> codec_failures(std::span<const DicomFileHeader* const> headers);

// Bytes per value of a stored type.
size_t stored_size(StoredType type);

// Smallest and largest stored value of one image (after BitsStored, before rescale).
struct StoredRange {
  int64_t lo = 0, hi = 0;
};

// The stored type of a file whose images read_stored_images can read: native little endian, one
// sample of 8, 16 or 32-bit integers, and every check decode_dicom_frames makes passed; nullopt
// for any other file (decode_dicom_frames decodes it, or says why it cannot).
std::optional<StoredType> native_stored_type(const DicomFileHeader& header);

// Reads the images (frames, or a mosaic's tiles) of a file of native_stored_type straight from
// the file: image i into images[i] (nullptr: not wanted), rows * columns stored values reduced to
// BitsStored (sign-extended when signed) and mirrored as decode_dicom_frames does, and its
// range into ranges[i]. False when the file cannot be read so (cut short since its header was
// read): decode_dicom_frames then says what is wrong with it.
bool read_stored_images(const DicomFileHeader& header, std::span<std::byte* const> images,
                        std::span<StoredRange> ranges);

// Decodes every frame of `header.file` (from `codec`, that file's decode_with_codecs result, when
// given) and applies each frame's RescaleSlope and RescaleIntercept; an RGB image (is_rgb_image)
// gives its colours and their luminance, unscaled. Throws imx::Error naming the file when it has
// no pixel data, is truncated or cannot be decoded, is neither MONOCHROME1/MONOCHROME2 with one
// sample per pixel nor is_rgb_image, or its size differs from the header's.
DecodedFrames decode_dicom_frames(const DicomFileHeader& header,
                                  const CodecPixels* codec = nullptr);

}  // namespace imx::detail
