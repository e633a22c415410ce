// Peak memory of reading every frame of a 4-D DICOM series (read_dicom_frames, what `intermix
// convert` does): the voxels and a bounded overhead, not the series' file list and frame labels
// once per frame (which grew with files x frames: 532 MB for an 80x80x6x480 series of 37 MB).
// A program of its own: see region_memory_test.cpp.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "intermix/dicom.hpp"
#include "peak_growth.hpp"
#include "pydicom_series.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

TEST(DicomFramesMemory, EveryFrameCostsItsVoxelsNotTheFileList) {
  SKIP_WITHOUT_SHARED_DATA("dicom/ts/1.dcm");
  if (!test::have_pydicom()) GTEST_SKIP() << "/usr/bin/python3 with pydicom is not available";
  constexpr int kVolumes = 200, kSlices = 4, kRows = 32, kColumns = 32;
  test::TempDir dir;
  // Long file names, as scanners' are: the file list is what must not be held once per frame.
  ASSERT_TRUE(test::run_pydicom(dir, R"PY(
orient = rotated_axial(0)
pos = positions(orient, 4, 3.0)
os.makedirs('in', exist_ok=True)
inst = 0
for v in range(200):
    for s in range(4):
        inst += 1
        def extra(ds, v=v):
            ds.TemporalPositionIdentifier = v + 1
        write('in/1.3.12.2.1107.5.2.43.67093.2022071112141808199812635.%06d.dcm' % inst, 32, 32,
              pos[s], orient, pixels(32, 32, 1.0 + 0.01 * v), '1.2.3.14', inst, extra,
              manufacturer='SIEMENS')
)PY"));
  const int64_t voxels_kib = int64_t{kVolumes} * kSlices * kRows * kColumns * 2 / 1024;
  test::PeakGrowth growth;
  const std::vector<DicomVolume> frames = read_dicom_frames(dir / "in");
  const int64_t grew = growth.kib();
  ASSERT_EQ(frames.size(), static_cast<size_t>(kVolumes));
  EXPECT_EQ(frames.front().series.files.size(), static_cast<size_t>(kVolumes * kSlices));
  EXPECT_EQ(frames.front().frame_labels.size(), static_cast<size_t>(kVolumes));
  // The voxels (twice, for a type change) and 16 MiB for headers, labels, threads and decoders
  // (9 MiB here; holding the file list and labels once per frame made it 204 MiB).
#ifndef IMX_SANITIZED  // AddressSanitizer's redzones and quarantine make resident memory no measure
  EXPECT_LT(grew, 2 * voxels_kib + 16 * 1024) << "voxels: " << voxels_kib << " KiB";
#endif
  std::printf("read_dicom_frames of %d files: peak grew %lld KiB for %lld KiB of voxels\n",
              kVolumes * kSlices, static_cast<long long>(grew), static_cast<long long>(voxels_kib));
}

}  // namespace
}  // namespace imx
