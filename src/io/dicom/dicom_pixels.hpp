// Decoding one DICOM file's pixels through GDCM (every transfer syntax it supports) into
// rescaled values, one float plane per frame.
#pragma once
#include <memory>
#include <new>
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
};

// Decodes every frame of `header.file` and applies each frame's RescaleSlope and
// RescaleIntercept. Throws imx::Error naming the file when it has no pixel data, is truncated or
// cannot be decoded, is not MONOCHROME1/MONOCHROME2 with one sample per pixel, or its size
// differs from the header's.
DecodedFrames decode_dicom_frames(const DicomFileHeader& header);

}  // namespace imx::detail
