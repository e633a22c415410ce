// FreeSurfer's per-vertex maps stored as volumes (27307x1x6 NIfTI, 163842x1x1 MGH): vertex v is
// voxel v with x fastest, checked against nibabel's get_fdata()[..., frame].ravel(order='F').
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "io/overlay/volume_overlay.hpp"
#include "nibabel_reference.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

// Each file X gets X.vertices: its frames' values as nibabel orders vertices, frame after
// frame, little-endian float64.
const char* const kVertexVolumeScript = R"PY(
rng = np.random.default_rng(11)
def vertices(path):
    d = np.asarray(nib.load(path).get_fdata(), dtype=np.float64)
    d = d.reshape(d.shape[:3] + (-1,))
    np.stack([d[..., f].ravel(order='F') for f in range(d.shape[3])]).astype('<f8').tofile(path + '.vertices')

# 42 vertices as FreeSurfer reshapes them (27307x1x6 for 163842), three frames.
img = nib.Nifti1Image(rng.normal(size=(7, 1, 6, 3)).astype(np.float32), np.eye(4))
img.to_filename('sig.nii.gz'); vertices('sig.nii.gz')
# Scaled integers, one frame.
img = nib.Nifti1Image(rng.integers(-300, 300, (7, 1, 6)).astype(np.int16), np.eye(4))
img.header.set_slope_inter(0.01, 2.0)
img.to_filename('scaled.nii'); vertices('scaled.nii')
nib.MGHImage(rng.uniform(1, 4, (42, 1, 1)).astype(np.float32), np.eye(4)).to_filename('lh.thickness.mgh')
vertices('lh.thickness.mgh')
)PY";

class VertexVolume : public test::NibabelFiles<&kVertexVolumeScript> {};

std::vector<double> nibabel_vertices(const std::filesystem::path& file) {
  const std::string bytes = test::read_bytes(file.string() + ".vertices");
  std::vector<double> v(bytes.size() / sizeof(double));
  std::memcpy(v.data(), bytes.data(), v.size() * sizeof(double));
  return v;
}

TEST_F(VertexVolume, EveryFrameIsNibabelsVoxelsInFortranOrder) {
  for (const char* name : {"sig.nii.gz", "scaled.nii", "lh.thickness.mgh"}) {
    const std::filesystem::path f = file(name);
    const std::vector<double> want = nibabel_vertices(f);
    const VolumeHeader header = read_volume_header(f);
    ASSERT_EQ(want.size(), 42u * static_cast<size_t>(header.frames)) << name;
    EXPECT_TRUE(detail::is_vertex_volume_shape(header.dims, 42)) << name;
    for (int frame = 0; frame < header.frames; ++frame) {
      const detail::VertexOverlay o =
          detail::volume_as_overlay(read_volume(f, frame), 42, f.string());
      ASSERT_EQ(o.values.size(), 42u);
      EXPECT_EQ(o.claimed_vertices, 42u);
      for (size_t v = 0; v < 42; ++v)
        EXPECT_NEAR(o.values[v], want[frame * 42 + v],
                    1e-6 * std::max(1.0, std::abs(want[frame * 42 + v])))
            << name << " frame " << frame << " vertex " << v;
    }
  }
  EXPECT_EQ(read_volume_header(file("sig.nii.gz")).frames, 3);
  test::expect_error([&] { detail::volume_as_overlay(read_volume(file("sig.nii.gz")), 43, "sig"); },
                     {"sig: 7x1x6 = 42 voxels, but the surface has 43 vertices"});
}

TEST(VertexVolumeShape, OnlyAnAxisOfOneAndTheVertexCountMakeAnOverlay) {
  EXPECT_TRUE(detail::is_vertex_volume_shape({27307, 1, 6}, 163842));
  EXPECT_TRUE(detail::is_vertex_volume_shape({163842, 1, 1}, 163842));
  EXPECT_FALSE(detail::is_vertex_volume_shape({27307, 1, 6}, 163841));
  // As many voxels, but a 3-D grid: an image, whatever its count.
  EXPECT_FALSE(detail::is_vertex_volume_shape({2, 3, 7}, 42));
  EXPECT_FALSE(detail::is_vertex_volume_shape({256, 256, 170}, 256 * 256 * 170));
}

}  // namespace
}  // namespace imx
