// MINC-2 against nibabel.minc2: files written with h5py in MINC-2's layout (short and uint16 with
// per-slice image-min/max and valid_range clipping, float and double, oblique direction cosines
// with a negative step, time first and in the middle, another dimension order, a scaling that
// changes nothing) and nibabel's own MINC-2 test files, each read by intermix and by nibabel:
// intermix must give nibabel's dims, affine (in LPS) and every voxel of every frame. Then the
// refusals: MINC-1 (with the way to convert), and what nibabel refuses.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "expect_error.hpp"
#include "io/volume/minc.hpp"
#include "nibabel_reference.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using detail::read_minc;
using detail::read_minc_header;
using detail::read_minc_region;
using test::expect_equals_reference;
using test::expect_error;
using test::NibabelImage;
using test::read_reference;

const char* kScript = R"PY(
import json, shutil, warnings
try:
    import h5py
except ImportError:
    open('no_h5py', 'w').close()
    sys.exit(0)
warnings.simplefilter('ignore')
rng = np.random.default_rng(11)

def minc(name, data, dimorder, dims, scale=None, valid_range=None, image_attrs=None):
    """A MINC-2 file as libminc lays it out: dims = {name: attrs}, scale = (min, max, dimorder)."""
    with h5py.File(name, 'w') as f:
        root = f.create_group('minc-2.0')
        root.attrs['ident'] = np.bytes_('intermix-test')
        for dname, attrs in dims.items():
            d = root.create_dataset('dimensions/' + dname, data=np.int32(0))
            d.attrs['spacing'] = np.bytes_(attrs.pop('spacing', 'regular__'))
            if dname in dimorder.split(','):
                d.attrs['length'] = np.uint32(data.shape[dimorder.split(',').index(dname)])
            for k, v in attrs.items():
                d.attrs[k] = np.bytes_(v) if isinstance(v, str) else np.asarray(v, dtype=np.float64)
        img = root.create_dataset('image/0/image', data=data, chunks=True, compression='gzip')
        img.attrs['dimorder'] = np.bytes_(dimorder)
        if valid_range is not None:
            img.attrs['valid_range'] = np.asarray(valid_range, dtype=np.float64)
        for k, v in (image_attrs or {}).items():
            img.attrs[k] = v
        lo, hi, order = scale if scale is not None else (0.0, 1.0, None)
        for key, values in (('image-min', lo), ('image-max', hi)):
            s = root.create_dataset('image/0/' + key, data=np.asarray(values, dtype=np.float64))
            if order:
                s.attrs['dimorder'] = np.bytes_(order)

def ref_minc(name):
    """name.ref as ref() writes it, with nibabel's time axis (if any) moved last."""
    img = nib.load(name)
    data = np.asarray(img.get_fdata(), dtype=np.float64)
    order = h5py.File(name, 'r')['minc-2.0/image/0/image'].attrs['dimorder'].decode().split(',')
    if 'time' in order:
        data = np.moveaxis(data, order.index('time'), -1)
    frames = data.reshape(data.shape[:3] + (-1,), order='F')
    with open(name + '.ref', 'wb') as f:
        np.array([frames.shape[3]] + list(frames.shape[:3]), dtype='<i8').tofile(f)
        np.asarray(img.affine, dtype='<f8').tofile(f)
        frames.ravel(order='F').astype('<f8').tofile(f)

c, s = np.cos(0.3), np.sin(0.3)
oblique = {'xspace': {'start': -40.5, 'step': 1.5, 'direction_cosines': [c, s, 0.0], 'units': 'mm'},
           'yspace': {'start': 22.0, 'step': -0.75, 'direction_cosines': [-s, c, 0.0]},
           'zspace': {'start': -7.25, 'step': 2.0, 'direction_cosines': [0.0, 0.0, 1.0]}}
def dims(**extra):
    out = {k: dict(v) for k, v in oblique.items()}
    out.update(extra)
    return out

# short, per-slice (zspace) image-min/max, a valid_range the data exceeds (clipped), oblique.
short = rng.integers(-1500, 1500, size=(5, 6, 7)).astype(np.int16)
minc('short.mnc', short, 'zspace,yspace,xspace', dims(),
     scale=(rng.uniform(-50, 0, 5), rng.uniform(100, 900, 5), 'zspace'), valid_range=[-1000, 1000])
# float32 and float64: read as they are.
minc('float.mnc', rng.standard_normal((4, 5, 6)).astype(np.float32) * 30, 'zspace,yspace,xspace',
     dims(), scale=(0.0, 1.0, None))
minc('double.mnc', rng.standard_normal((3, 4, 5)) * 1e3, 'zspace,yspace,xspace', dims())
# 4-D: time first, uint8 scaled per frame and slice.
minc('time.mnc', rng.integers(0, 256, size=(3, 4, 5, 6)).astype(np.uint8), 'time,zspace,yspace,xspace',
     dims(time={'start': 0.0, 'step': 2.5, 'units': 's'}),
     scale=(rng.uniform(-5, 0, (3, 4)), rng.uniform(10, 20, (3, 4)), 'time,zspace'), valid_range=[0, 255])
# Another dimension order, uint16 scaled along the first (xspace) dimension, no valid_range.
minc('order.mnc', rng.integers(0, 65535, size=(6, 4, 5)).astype(np.uint16), 'xspace,zspace,yspace',
     dims(), scale=(rng.uniform(0, 1, 6), rng.uniform(2, 3, 6), 'xspace'))
# Scaling that changes nothing: uint8 stays uint8.
minc('identity.mnc', rng.integers(0, 256, size=(4, 5, 6)).astype(np.uint8), 'zspace,yspace,xspace',
     {'xspace': {}, 'yspace': {}, 'zspace': {}}, scale=(0.0, 255.0, None), valid_range=[0, 255])
# Time in the middle, int32 scaled with one pair.
minc('middle.mnc', rng.integers(-10**6, 10**6, size=(4, 2, 5, 3)).astype(np.int32),
     'zspace,time,yspace,xspace', dims(time={'step': 1.0}), scale=(-3.0, 7.0, None))
for name in ['short.mnc', 'float.mnc', 'double.mnc', 'time.mnc', 'order.mnc', 'identity.mnc', 'middle.mnc']:
    ref_minc(name)
# nibabel's own MINC-2 test files, and its MINC-1 ones (refused).
data = os.path.dirname(nib.__file__) + '/tests/data/'
for name in ['minc2_1_scale.mnc', 'minc2_4d.mnc', 'minc2-4d-d.mnc', 'minc2-no-att.mnc', 'small.mnc',
             'tiny.mnc', 'minc1_4d.mnc']:
    if os.path.exists(data + name):
        shutil.copy(data + name, name)
        if name not in ('tiny.mnc', 'minc1_4d.mnc'):
            ref_minc(name)

# What nibabel refuses: written here, each checked to be refused by nibabel.
minc('irregular.mnc', short, 'zspace,yspace,xspace', dims(xspace={'spacing': 'irregular'}),
     scale=(0.0, 1.0, None))
minc('range.mnc', short.astype(np.uint8), 'zspace,yspace,xspace', dims(), scale=(0.0, 1.0, None),
     valid_range=[0, 300])
minc('flat.mnc', short[0], 'yspace,xspace', dims(), scale=(0.0, 1.0, None))
minc('vector.mnc', rng.integers(0, 9, size=(4, 5, 6, 3)).astype(np.uint8),
     'zspace,yspace,xspace,vector_dimension', dims(vector_dimension={}), scale=(0.0, 1.0, None))
b = open('short.mnc', 'rb').read()
open('truncated.mnc', 'wb').write(b[: len(b) // 2])
refused = {}
for name in ['irregular.mnc', 'range.mnc', 'flat.mnc', 'truncated.mnc']:
    try:
        nib.load(name).get_fdata()
        refused[name] = 'nibabel read it'
    except Exception as e:
        refused[name] = repr(e)
json.dump(refused, open('refused.json', 'w'))
)PY";

class Minc : public test::NibabelFiles<&kScript> {
 protected:
  void SetUp() override {
    test::NibabelFiles<&kScript>::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    if (fs::exists(file("no_h5py"))) GTEST_SKIP() << "/usr/bin/python3 has no h5py";
  }
  static void expect_frames_equal_nibabel(const std::string& name, VoxelType type) {
    SCOPED_TRACE(name);
    const NibabelImage ref = read_reference(file(name));
    const VolumeHeader header = read_minc_header(file(name));
    EXPECT_EQ(header.dims, ref.dims);
    EXPECT_EQ(header.frames, ref.frames);
    EXPECT_EQ(header.type, type);
    for (int k = 0; k < ref.frames; ++k) {
      const VolumeData v = read_minc(file(name), k);
      EXPECT_EQ(v.type(), type);
      expect_equals_reference(v, ref, k, name);
    }
  }
};

TEST_F(Minc, ScaledShortFloatAndDoubleEqualNibabel) {
  expect_frames_equal_nibabel("short.mnc", VoxelType::f32);
  expect_frames_equal_nibabel("float.mnc", VoxelType::f32);
  expect_frames_equal_nibabel("double.mnc", VoxelType::f32);
}

TEST_F(Minc, TimeFramesAndDimensionOrdersEqualNibabel) {
  expect_frames_equal_nibabel("time.mnc", VoxelType::f32);
  expect_frames_equal_nibabel("middle.mnc", VoxelType::f32);
  expect_frames_equal_nibabel("order.mnc", VoxelType::f32);
  const VolumeHeader h = read_minc_header(file("time.mnc"));
  ASSERT_EQ(h.frame_labels.size(), 3u);
  EXPECT_DOUBLE_EQ(*h.frame_labels[2].time_s, 5.0);  // step 2.5 s
}

TEST_F(Minc, ScalingThatChangesNothingKeepsTheType) {
  expect_frames_equal_nibabel("identity.mnc", VoxelType::u8);
}

TEST_F(Minc, NibabelsOwnTestFilesEqualNibabel) {
  for (const char* name :
       {"minc2_1_scale.mnc", "minc2_4d.mnc", "minc2-4d-d.mnc", "minc2-no-att.mnc", "small.mnc"}) {
    if (!fs::exists(file(name))) continue;  // not every nibabel package ships its test data
    const VolumeHeader h = read_minc_header(file(name));
    expect_frames_equal_nibabel(name, h.type);
  }
}

TEST_F(Minc, RegionsAreCropsOfTheWhole) {
  for (const char* name : {"short.mnc", "order.mnc", "middle.mnc"}) {
    SCOPED_TRACE(name);
    const int frame = read_minc_header(file(name)).frames - 1;
    const VolumeData whole = read_minc(file(name), frame);
    const VoxelBox box{{1, 2, 1}, whole.dims - glm::ivec3(1, 0, 1)};
    const VolumeData region = read_minc_region(file(name), box, frame);
    const VolumeData cropped = crop(whole, box, name);
    ASSERT_EQ(region.dims, cropped.dims);
    EXPECT_EQ(region.index_to_world, cropped.index_to_world);
    int differing = 0;
    for (int k = 0; k < region.dims.z; ++k)
      for (int j = 0; j < region.dims.y; ++j)
        for (int i = 0; i < region.dims.x; ++i)
          differing += region.value_at(i, j, k) != cropped.value_at(i, j, k);
    EXPECT_EQ(differing, 0);
  }
  expect_error([&] { read_minc(file("time.mnc"), 3); }, {"frame"});
}

TEST_F(Minc, RefusesMinc1NamingTheConversion) {
  for (const char* name : {"tiny.mnc", "minc1_4d.mnc"}) {
    if (!fs::exists(file(name))) continue;
    EXPECT_TRUE(detail::is_minc(test::read_bytes(file(name)).substr(0, 8)));
    expect_error([&] { read_minc_header(file(name)); }, {name, "MINC-1", "mincconvert -2"});
  }
  const test::TempDir dir;
  const fs::path cdf2 = dir.write("v2.mnc", std::string("CDF\x02", 4) + std::string(60, '\0'));
  expect_error([&] { read_minc(cdf2); }, {"MINC-1", "nibabel"});
}

TEST_F(Minc, RefusesWhatNibabelRefuses) {
  const nlohmann::json nibabel = nlohmann::json::parse(test::read_bytes(file("refused.json")));
  for (const auto& [name, said] : nibabel.items())
    EXPECT_NE(said.get<std::string>(), "nibabel read it") << name;
  expect_error([&] { read_minc(file("irregular.mnc")); }, {"xspace", "irregular spacing"});
  expect_error([&] { read_minc(file("range.mnc")); }, {"valid_range 0 .. 300", "uint8"});
  expect_error([&] { read_minc_header(file("flat.mnc")); }, {"2 spatial dimensions"});
  expect_error([&] { read_minc_header(file("vector.mnc")); },
               {"'vector_dimension'", "not supported"});
  expect_error([&] { read_minc(file("truncated.mnc")); }, {"truncated.mnc", "HDF5"});
  const test::TempDir dir;
  const fs::path junk =
      dir.write("junk.mnc", std::string("\x89HDF\r\n\x1a\n", 8) + std::string(500, 'x'));
  expect_error([&] { read_minc(junk); }, {"junk.mnc"});
  const fs::path text = dir.write("text.mnc", "not a volume");
  expect_error([&] { read_minc(text); }, {"HDF5's signature"});
  EXPECT_FALSE(detail::is_minc("not a volume"));
}

}  // namespace
}  // namespace imx
