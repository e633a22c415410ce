// NIfTI colour images (RGB24, RGBA32; 3-D and 4-D) read as colour volumes: every voxel's colour
// as nibabel reads it (a structured R, G, B[, A] dtype), the scalar its luminance (or alpha), the
// placement nibabel's.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "intermix/io.hpp"
#include "nibabel_reference.hpp"
#include "shared_data.hpp"
#include "volume/colour_grid.hpp"

namespace imx {
namespace {

// Appended to the nibabel prelude: cref(path) writes path + ".cref": frames, the three dims and
// the channel count (int64), nibabel's affine (RAS, row by row) and every frame's channels as
// nibabel reads them, voxel after voxel (x fastest), channels interleaved, frame after frame.
const char* kColourRef = R"PY(
RGB = np.dtype([('R', 'u1'), ('G', 'u1'), ('B', 'u1')])
RGBA = np.dtype([('R', 'u1'), ('G', 'u1'), ('B', 'u1'), ('A', 'u1')])

def cref(path):
    img = nib.load(path)
    d = np.asanyarray(img.dataobj)
    if d.ndim == 3:
        d = d[..., None]
    ch = np.stack([d[n] for n in d.dtype.names], axis=-1)
    with open(path + '.cref', 'wb') as f:
        np.array([d.shape[3]] + list(d.shape[:3]) + [ch.shape[-1]], dtype='<i8').tofile(f)
        np.asarray(img.affine, dtype='<f8').tofile(f)
        ch.transpose(3, 2, 1, 0, 4).astype('u1').tofile(f)

def colour_image(shape, dtype, seed):
    rng = np.random.default_rng(seed)
    a = np.zeros(shape, dtype=dtype)
    for n in dtype.names:
        a[n] = rng.integers(0, 256, size=shape)
    return a

oblique = np.array([[1.8, 0.2, 0.0, -20.0], [-0.1, 2.1, 0.3, 15.0], [0.0, -0.2, 2.5, -7.0],
                    [0, 0, 0, 1]])
)PY";

struct ColourReference {
  int frames = 0, channels = 0;
  glm::ivec3 dims{0};
  glm::dmat4 lps{1.0};
  std::vector<uint8_t> bytes;

  const uint8_t* voxel(int frame, size_t i) const {
    const size_t n = static_cast<size_t>(dims.x) * dims.y * dims.z;
    return bytes.data() + (static_cast<size_t>(frame) * n + i) * channels;
  }
};

ColourReference read_colour_reference(const std::filesystem::path& image) {
  const std::string bytes = test::read_bytes(image.string() + ".cref");
  ColourReference r;
  int64_t head[5] = {};
  if (bytes.size() < sizeof head + 16 * sizeof(double)) {
    ADD_FAILURE() << "no nibabel reference for " << image;
    return r;
  }
  std::memcpy(head, bytes.data(), sizeof head);
  r.frames = static_cast<int>(head[0]);
  r.dims = {static_cast<int>(head[1]), static_cast<int>(head[2]), static_cast<int>(head[3])};
  r.channels = static_cast<int>(head[4]);
  double affine[16];
  std::memcpy(affine, bytes.data() + sizeof head, sizeof affine);
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 4; ++col)
      r.lps[col][row] = (row < 2 ? -1.0 : 1.0) * affine[4 * row + col];
  r.bytes.assign(bytes.begin() + sizeof head + sizeof affine, bytes.end());
  EXPECT_EQ(r.bytes.size(),
            static_cast<size_t>(r.frames) * r.dims.x * r.dims.y * r.dims.z * r.channels);
  return r;
}

// Frame `frame` of `v` holds nibabel's colours, its scalars their luminance (RGB) or the alpha
// (RGBA), at nibabel's placement.
void expect_colours(const VolumeData& v, const ColourReference& r, int frame,
                    const std::string& what) {
  ASSERT_EQ(v.dims, r.dims) << what;
  ASSERT_EQ(v.type(), VoxelType::u8) << what;
  ASSERT_TRUE(v.colours) << what << ": read without its colours";
  for (int c = 0; c < 4; ++c)
    for (int row = 0; row < 4; ++row)
      EXPECT_NEAR(v.index_to_world[c][row], r.lps[c][row], 1e-4) << what << " affine";
  int wrong = 0;
  for (size_t i = 0; i < v.voxel_count(); ++i) {
    const uint8_t* want = r.voxel(frame, i);
    const uint8_t* got = v.colours->rgb.data() + 3 * i;
    const uint8_t scalar = r.channels == 4 ? want[3] : colour_luminance(want[0], want[1], want[2]);
    const uint8_t got_scalar = std::get<VoxelBuffer<uint8_t>>(v.voxels)[i];
    if ((std::memcmp(got, want, 3) != 0 || got_scalar != scalar) && wrong++ < 5)
      ADD_FAILURE() << what << " frame " << frame << " voxel " << i << ": (" << int(got[0]) << ","
                    << int(got[1]) << "," << int(got[2]) << ") scalar " << int(got_scalar)
                    << ", nibabel reads (" << int(want[0]) << "," << int(want[1]) << ","
                    << int(want[2]) << ") scalar " << int(scalar);
  }
  EXPECT_EQ(wrong, 0) << what;
}

const char* kColourFiles = R"PY(
img = nib.Nifti1Image(colour_image((7, 5, 4), RGB, 1), oblique)
nib.save(img, 'rgb.nii'); cref('rgb.nii')
img = nib.Nifti1Image(colour_image((6, 5, 3, 3), RGB, 2), oblique)
nib.save(img, 'rgb4d.nii.gz'); cref('rgb4d.nii.gz')
img = nib.Nifti1Image(colour_image((5, 6, 4), RGBA, 3), np.diag([2.0, 3.0, 4.0, 1.0]))
nib.save(img, 'rgba.nii'); cref('rgba.nii')
img = nib.Nifti1Image(colour_image((4, 3, 5, 2), RGBA, 4), oblique)
nib.save(img, 'rgba4d.nii.gz'); cref('rgba4d.nii.gz')
img = nib.Nifti2Image(colour_image((5, 4, 3), RGB, 5), oblique)
nib.save(img, 'rgb2.nii'); cref('rgb2.nii')
)PY";
const std::string kColourScript = std::string(kColourRef) + kColourFiles;
const char* const kColourScriptText = kColourScript.c_str();

using ColourNifti = test::NibabelFiles<&kColourScriptText>;

TEST_F(ColourNifti, Rgb24AndRgba32ReadWithNibabelsColours) {
  for (const char* name : {"rgb.nii", "rgb4d.nii.gz", "rgba.nii", "rgba4d.nii.gz", "rgb2.nii"}) {
    const ColourReference r = read_colour_reference(file(name));
    const VolumeHeader h = read_volume_header(file(name));
    EXPECT_EQ(h.frames, r.frames) << name;
    EXPECT_EQ(h.type, VoxelType::u8) << name;
    for (int f = 0; f < r.frames; ++f) expect_colours(read_volume(file(name), f), r, f, name);
  }
}

TEST_F(ColourNifti, ARegionHoldsItsPartOfTheColours) {
  const VoxelBox box{{1, 2, 1}, {6, 5, 3}};
  for (const char* name : {"rgb.nii", "rgb4d.nii.gz"}) {
    const VolumeData all = read_volume(file(name), 1 % read_volume_header(file(name)).frames);
    const VolumeData part =
        read_volume_region(file(name), box, 1 % read_volume_header(file(name)).frames);
    const VolumeData cut = crop(all, box, name);
    ASSERT_TRUE(part.colours && cut.colours) << name;
    EXPECT_EQ(part.colours->rgb, cut.colours->rgb) << name;
    EXPECT_EQ(std::get<VoxelBuffer<uint8_t>>(part.voxels).size(), box.count()) << name;
    EXPECT_EQ(part.index_to_world, cut.index_to_world) << name;
  }
}

// A DTI colour-FA map as FSL and dcm2niix users have them: RGB24, FA times the principal
// direction's absolute components, made here from the shared scalar FA map.
TEST(ColourNiftiFa, ColourFaMapReadsWithNibabelsColours) {
  SKIP_WITHOUT_SHARED_DATA("neuro/volumes/FA.nii.gz");
  if (!test::have_nibabel()) GTEST_SKIP() << "/usr/bin/python3 with nibabel is not available";
  test::TempDir dir;
  const std::string script = std::string(kColourRef) + R"PY(
fa_img = nib.load(os.environ['FA'])
fa = np.clip(np.asarray(fa_img.get_fdata(), dtype=np.float64), 0, 1)
g = np.stack(np.gradient(fa), axis=-1)
v = np.abs(g) / np.maximum(np.linalg.norm(g, axis=-1, keepdims=True), 1e-9)
rgb = np.zeros(fa.shape, dtype=RGB)
for k, n in enumerate('RGB'):
    rgb[n] = np.round(255 * fa * v[..., k]).astype(np.uint8)
img = nib.Nifti1Image(rgb, fa_img.affine, fa_img.header)
img.set_data_dtype(RGB)
nib.save(img, 'colour_fa.nii.gz'); cref('colour_fa.nii.gz')
)PY";
  setenv("FA", test::shared_data("neuro/volumes/FA.nii.gz").c_str(), 1);
  ASSERT_TRUE(test::run_nibabel(dir, script));
  const ColourReference r = read_colour_reference(dir / "colour_fa.nii.gz");
  const VolumeData v = read_volume(dir / "colour_fa.nii.gz");
  expect_colours(v, r, 0, "colour_fa.nii.gz");
  // A colour map, not a black one: many voxels have colour.
  size_t coloured = 0;
  for (size_t i = 0; i < v.voxel_count(); ++i)
    coloured += v.colours->rgb[3 * i] + v.colours->rgb[3 * i + 1] + v.colours->rgb[3 * i + 2] > 60;
  EXPECT_GT(coloured, v.voxel_count() / 20);
}

}  // namespace
}  // namespace imx
