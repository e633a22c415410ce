// Files written and read by nibabel (Debian's /usr/bin/python3), the reference the NIfTI,
// Analyze and MGH readers are checked against: a test's Python snippet writes image files and,
// through ref(), what nibabel.load reads from them (its affine and get_fdata()), which the test
// then compares with what intermix reads.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/mat4x4.hpp>

#include "intermix/volume.hpp"
#include "temp_dir.hpp"

namespace imx::test {

// Whether /usr/bin/python3 has nibabel and numpy (checked once).
inline bool have_nibabel() {
  static const bool ok =
      std::system("/usr/bin/python3 -c 'import nibabel, numpy' >/dev/null 2>&1") == 0;
  return ok;
}

// Prepended to every snippet: imports, and ref(path), which writes path + ".ref": the frame
// count, the grid's three dims, nibabel's affine (RAS, 16 doubles, row by row) and every frame's
// get_fdata() voxels (x fastest, frame after frame), all little-endian.
inline const char* kNibabelPrelude = R"PY(
import os, sys
import numpy as np
import nibabel as nib

def ref(path):
    img = nib.load(path)
    data = np.asarray(img.get_fdata(), dtype=np.float64)
    frames = data.reshape(data.shape[:3] + (-1,), order='F')
    with open(path + '.ref', 'wb') as f:
        np.array([frames.shape[3]] + list(frames.shape[:3]), dtype='<i8').tofile(f)
        np.asarray(img.affine, dtype='<f8').tofile(f)
        frames.ravel(order='F').astype('<f8').tofile(f)
)PY";

// Runs the prelude and `snippet` in `dir` (the working folder); false (with the script's output
// as a test failure) when Python fails.
inline bool run_nibabel(const TempDir& dir, const std::string& snippet) {
  write_bytes(dir / "make.py", std::string(kNibabelPrelude) + snippet);
  const std::string command =
      "cd '" + dir.path().string() + "' && /usr/bin/python3 make.py >make.log 2>&1";
  if (std::system(command.c_str()) == 0) return true;
  ADD_FAILURE() << "nibabel script failed:\n" << read_bytes(dir / "make.log");
  return false;
}

// A fixture whose suite has `*Script` write its files once, with nibabel, into a folder of its
// own (file(name) is there); its tests skip where /usr/bin/python3 has no nibabel.
template <const char* const* Script>
class NibabelFiles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!have_nibabel()) return;
    dir_ = new TempDir;
    ok_ = run_nibabel(*dir_, *Script);
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override {
    if (!have_nibabel()) GTEST_SKIP() << "/usr/bin/python3 with nibabel is not available";
    ASSERT_TRUE(ok_) << "nibabel could not write the test files";
  }
  static std::filesystem::path file(const std::string& name) { return *dir_ / name; }

 private:
  inline static TempDir* dir_ = nullptr;
  inline static bool ok_ = false;
};

// What nibabel read from a file: ref()'s output.
struct NibabelImage {
  int frames = 0;
  glm::ivec3 dims{0};
  glm::dmat4 lps{1.0};       // its affine, RAS converted to LPS (x and y rows negated)
  std::vector<double> data;  // frames * dims voxels

  double at(int frame, int i, int j, int k) const {
    return data[((static_cast<size_t>(frame) * dims.z + k) * dims.y + j) * dims.x + i];
  }
};

inline NibabelImage read_reference(const std::filesystem::path& image) {
  const std::string bytes = read_bytes(image.string() + ".ref");
  NibabelImage r;
  int64_t head[4] = {0, 0, 0, 0};
  if (bytes.size() < sizeof head + 16 * sizeof(double)) {
    ADD_FAILURE() << "no nibabel reference for " << image;
    return r;
  }
  std::memcpy(head, bytes.data(), sizeof head);
  r.frames = static_cast<int>(head[0]);
  r.dims =
      glm::ivec3(static_cast<int>(head[1]), static_cast<int>(head[2]), static_cast<int>(head[3]));
  double affine[16];
  std::memcpy(affine, bytes.data() + sizeof head, sizeof affine);
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 4; ++col)
      r.lps[col][row] = (row < 2 ? -1.0 : 1.0) * affine[4 * row + col];
  const size_t start = sizeof head + sizeof affine;
  r.data.resize((bytes.size() - start) / sizeof(double));
  std::memcpy(r.data.data(), bytes.data() + start, r.data.size() * sizeof(double));
  EXPECT_EQ(r.data.size(), static_cast<size_t>(r.frames) * r.dims.x * r.dims.y * r.dims.z) << image;
  return r;
}

// `v` (frame `frame` as intermix read it) equals nibabel's: dims, every voxel (to float32's
// precision, as scaled voxels are float32) and the affine to 1e-4.
inline void expect_equals_reference(const VolumeData& v, const NibabelImage& r, int frame,
                                    const std::string& what) {
  ASSERT_EQ(v.dims, r.dims) << what;
  for (int c = 0; c < 4; ++c)
    for (int row = 0; row < 4; ++row)
      EXPECT_NEAR(v.index_to_world[c][row], r.lps[c][row], 1e-4)
          << what << ": affine entry [" << c << "][" << row << "]";
  int wrong = 0;
  for (int k = 0; k < r.dims.z; ++k)
    for (int j = 0; j < r.dims.y; ++j)
      for (int i = 0; i < r.dims.x; ++i) {
        const double want = r.at(frame, i, j, k), got = v.value_at(i, j, k);
        if (std::abs(got - want) > 1e-6 * std::max(1.0, std::abs(want)) && wrong++ < 5)
          ADD_FAILURE() << what << " frame " << frame << ": voxel (" << i << "," << j << "," << k
                        << ") is " << got << ", nibabel reads " << want;
      }
  EXPECT_EQ(wrong, 0) << what << " frame " << frame << ": voxels differing from nibabel's";
}

}  // namespace imx::test
