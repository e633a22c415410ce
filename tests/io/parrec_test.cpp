// Philips PAR/REC against nibabel.parrec: every PAR file of nibabel's own test data (Debian ships
// them with python3-nibabel) beside its REC, or a REC of random slices where nibabel ships none;
// each is read by intermix and by nibabel, and intermix must give nibabel's dims, frames, affine
// (in LPS), b values and vectors and the same voxels (per-frame checksums nibabel computes), or
// refuse where nibabel refuses. Then the refusals of edited headers and a short REC.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "expect_error.hpp"
#include "io/volume/parrec.hpp"
#include "nibabel_reference.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using detail::read_parrec;
using detail::read_parrec_header;
using detail::read_parrec_region;
using test::expect_error;

const char* kScript = R"PY(
import glob, json, shutil, warnings
from nibabel import parrec
warnings.simplefilter('ignore')
data = os.path.dirname(nib.__file__) + '/tests/data'
rng = np.random.default_rng(7)
out = {}
for src in sorted(glob.glob(data + '/*.PAR')):
    name = os.path.basename(src)
    shutil.copy(src, name)
    rec = name[:-4] + '.REC'
    try:
        with open(name, 'rt') as f:
            hdr = parrec.PARRECHeader.from_fileobj(f)
        shape, dt = hdr.get_rec_shape(), hdr.get_data_dtype()
    except Exception:
        shape, dt = None, None
    if os.path.exists(src[:-4] + '.REC'):
        shutil.copy(src[:-4] + '.REC', rec)
    elif shape is not None:
        top = 4096 if dt.itemsize == 2 else 256
        rng.integers(0, top, size=int(np.prod(shape))).astype(dt).tofile(rec)
    else:
        open(rec, 'wb').write(b'\0' * 4096)
    entry = {}
    try:
        img = nib.load(name)
        d = np.asarray(img.get_fdata(), dtype=np.float64)
        d = d.reshape(d.shape[:3] + (-1,), order='F')
        w = (np.arange(np.prod(d.shape[:3])) % 251 + 1).astype(np.float64)
        entry['dims'] = list(d.shape[:3])
        entry['frames'] = d.shape[3]
        entry['affine'] = img.affine.tolist()
        fr = [np.ravel(d[..., f], order='F') for f in range(d.shape[3])]
        entry['sum'] = [float(x.sum()) for x in fr]
        entry['wsum'] = [float((x * w).sum()) for x in fr]
        entry['abs'] = [float(np.abs(x).sum()) for x in fr]
        entry['samples'] = [[float(x[i]) for i in (0, len(x) // 3, len(x) - 1)] for x in fr]
        bvals, bvecs = img.header.get_bvals_bvecs()
        if bvals is not None:
            entry['bvals'] = bvals.tolist()
        if bvecs is not None:
            entry['bvecs'] = bvecs.tolist()
    except Exception as e:
        entry['error'] = repr(e)
    out[name] = entry
json.dump(out, open('parrec.json', 'w'), indent=1)
)PY";

class ParRec : public test::NibabelFiles<&kScript> {
 protected:
  static const nlohmann::json& reference() {
    static const nlohmann::json ref = nlohmann::json::parse(test::read_bytes(file("parrec.json")));
    return ref;
  }
};

// Sums over one frame, weighted as the script weighs them (linear index % 251 + 1).
struct Sums {
  double sum = 0, weighted = 0, abs = 0;
};
Sums sums_of(const VolumeData& v) {
  Sums s;
  size_t n = 0;
  for (int k = 0; k < v.dims.z; ++k)
    for (int j = 0; j < v.dims.y; ++j)
      for (int i = 0; i < v.dims.x; ++i, ++n) {
        const double x = v.value_at(i, j, k);
        s.sum += x;
        s.weighted += x * static_cast<double>(n % 251 + 1);
        s.abs += std::abs(x);
      }
  return s;
}

TEST_F(ParRec, EveryNibabelTestFileReadsAsNibabelReadsItOrIsRefusedAsNibabelRefusesIt) {
  int read = 0, refused = 0;
  for (const auto& [name, ref] : reference().items()) {
    SCOPED_TRACE(name);
    const fs::path par = file(name);
    if (ref.contains("error")) {
      // nibabel refuses it: so must intermix, with a message naming the file.
      expect_error([&] { read_parrec_header(par); }, {par.string()});
      expect_error([&] { read_parrec(par, 0); }, {par.string()});
      ++refused;
      continue;
    }
    ++read;
    const VolumeHeader h = read_parrec_header(par);
    const glm::ivec3 dims(ref["dims"][0].get<int>(), ref["dims"][1].get<int>(),
                          ref["dims"][2].get<int>());
    ASSERT_EQ(h.dims, dims);
    ASSERT_EQ(h.frames, ref["frames"].get<int>());
    EXPECT_EQ(h.type, VoxelType::f32);
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 4; ++col) {
        const double ras = ref["affine"][row][col].get<double>();
        EXPECT_NEAR(h.index_to_world[col][row], row < 2 ? -ras : ras, 1e-6)
            << "affine row " << row << " column " << col;
      }
    if (ref.contains("bvals")) {
      ASSERT_EQ(h.frame_labels.size(), static_cast<size_t>(h.frames));
      for (int f = 0; f < h.frames; ++f) {
        const FrameLabel& label = h.frame_labels[static_cast<size_t>(f)];
        ASSERT_TRUE(label.b_value.has_value()) << "frame " << f;
        EXPECT_DOUBLE_EQ(*label.b_value, ref["bvals"][f].get<double>()) << "frame " << f;
        if (ref.contains("bvecs")) {
          ASSERT_TRUE(label.b_vector.has_value()) << "frame " << f;
          for (int a = 0; a < 3; ++a)
            EXPECT_NEAR((*label.b_vector)[a], ref["bvecs"][f][a].get<double>(), 1e-12)
                << "frame " << f << " axis " << a;
        } else {
          EXPECT_FALSE(label.b_vector.has_value()) << "frame " << f << ": V4 has no directions";
        }
      }
    }
    // First, middle and last frames, every voxel through the checksums.
    std::vector<int> frames{0, h.frames / 2, h.frames - 1};
    frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
    for (int f : frames) {
      const VolumeData v = read_parrec(par, f);
      ASSERT_EQ(v.dims, dims);
      EXPECT_EQ(v.index_to_world, h.index_to_world);
      const Sums s = sums_of(v);
      const double scale = std::max(1.0, ref["abs"][f].get<double>());
      // float32 voxels against nibabel's float64: each within 2^-24 of its value.
      EXPECT_NEAR(s.sum, ref["sum"][f].get<double>(), 1e-6 * scale) << "frame " << f;
      EXPECT_NEAR(s.abs, ref["abs"][f].get<double>(), 1e-6 * scale) << "frame " << f;
      EXPECT_NEAR(s.weighted, ref["wsum"][f].get<double>(), 1e-6 * 251 * scale) << "frame " << f;
      const size_t n = static_cast<size_t>(dims.x) * dims.y * dims.z;
      const size_t at[3] = {0, n / 3, n - 1};
      for (int p = 0; p < 3; ++p) {
        const int i = static_cast<int>(at[p] % dims.x),
                  j = static_cast<int>(at[p] / dims.x % dims.y),
                  k = static_cast<int>(at[p] / dims.x / dims.y);
        const double want = ref["samples"][f][p].get<double>();
        EXPECT_NEAR(v.value_at(i, j, k), want, 1e-6 * std::max(1.0, std::abs(want)))
            << "frame " << f << " voxel " << at[p];
      }
    }
  }
  // The data's mix: most files read, and the three nibabel refuses (a partial b-value table,
  // slices of several orientations, a truncated dynamic series) are refused.
  EXPECT_GE(read, 25);
  EXPECT_EQ(refused, 3);
}

TEST_F(ParRec, FrameLabelsSayWhatDiffersBetweenVolumes) {
  // T1_3echo_mag_real_imag_phase: 3 echoes x 4 image types; DTI: b values with directions.
  const VolumeHeader echoes = read_parrec_header(file("T1_3echo_mag_real_imag_phase.PAR"));
  ASSERT_EQ(echoes.frame_labels.size(), 12u);
  for (const FrameLabel& label : echoes.frame_labels) {
    EXPECT_TRUE(label.echo_time_ms.has_value()) << label.text;
    EXPECT_FALSE(label.image_type.empty()) << label.text;
  }
  const VolumeHeader dti = read_parrec_header(file("DTI.PAR"));
  ASSERT_EQ(dti.frame_labels.size(), 8u);
  EXPECT_NE(dti.frame_labels[1].text.find("b="), std::string::npos) << dti.frame_labels[1].text;
}

TEST_F(ParRec, ReadsThroughTheRecNameAndLowerCaseNamesAndRegions) {
  const test::TempDir dir;
  fs::copy_file(file("phantom_EPI_asc_CLEAR_2_1.PAR"), dir / "scan.par");
  fs::copy_file(file("phantom_EPI_asc_CLEAR_2_1.REC"), dir / "scan.rec");
  const VolumeData whole = read_parrec(file("phantom_EPI_asc_CLEAR_2_1.PAR"), 2);
  const VolumeData lower = read_parrec(dir / "scan.par", 2);
  const VolumeData by_rec = read_parrec(dir / "scan.rec", 2);
  const VolumeData by_upper_rec = read_parrec(file("phantom_EPI_asc_CLEAR_2_1.REC"), 2);
  for (const VolumeData* v : {&lower, &by_rec, &by_upper_rec}) {
    ASSERT_EQ(v->dims, whole.dims);
    EXPECT_EQ(v->index_to_world, whole.index_to_world);
    EXPECT_EQ(v->value_at(7, 50, 4), whole.value_at(7, 50, 4));
  }
  const VoxelBox box{{3, 5, 2}, {40, 61, 8}};
  const VolumeData region = read_parrec_region(file("phantom_EPI_asc_CLEAR_2_1.PAR"), box, 2);
  const VolumeData cropped = crop(whole, box, "whole");
  ASSERT_EQ(region.dims, cropped.dims);
  EXPECT_EQ(region.index_to_world, cropped.index_to_world);
  int differing = 0;
  for (int k = 0; k < region.dims.z; ++k)
    for (int j = 0; j < region.dims.y; ++j)
      for (int i = 0; i < region.dims.x; ++i)
        differing += region.value_at(i, j, k) != cropped.value_at(i, j, k);
  EXPECT_EQ(differing, 0);
  expect_error([&] { read_parrec(file("phantom_EPI_asc_CLEAR_2_1.PAR"), 3); }, {"frame"});
}

// Copies a nibabel PAR (edited by `edit`) and its REC (cut to `rec_bytes` when given) to `dir`.
fs::path edited_copy(const test::TempDir& dir, const fs::path& par, const fs::path& rec,
                     const std::function<void(std::string&)>& edit, size_t rec_bytes = 0) {
  std::string text = test::read_bytes(par);
  edit(text);
  const fs::path out = dir.write("edited.PAR", text);
  std::string data = test::read_bytes(rec);
  if (rec_bytes != 0) data.resize(rec_bytes);
  dir.write("edited.REC", data);
  return out;
}

void replace(std::string& text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
}

TEST_F(ParRec, RefusesAShortRecAnInconsistentTableAnUnknownVersionAndAMissingRec) {
  const test::TempDir dir;
  const fs::path par = file("phantom_EPI_asc_CLEAR_2_1.PAR"),
                 rec = file("phantom_EPI_asc_CLEAR_2_1.REC");
  // The REC must hold every slice the table lists.
  const fs::path short_rec = edited_copy(
      dir, par, rec, [](std::string&) {}, 221184 - 2);
  expect_error([&] { read_parrec(short_rec, 0); }, {"edited.REC", "221182 bytes", "221184"});
  expect_error([&] { read_parrec_header(short_rec); }, {"221182 bytes"});
  // The general information's slice count must be the table's.
  const fs::path slices = edited_copy(dir, par, rec, [](std::string& t) {
    replace(t, "Max. number of slices/locations    :   9",
            "Max. number of slices/locations    :   8");
  });
  expect_error([&] { read_parrec_header(slices); },
               {"edited.PAR", "9 distinct 'slice number' values", "is 8"});
  // As must its dynamics count.
  const fs::path dynamics = edited_copy(dir, par, rec, [](std::string& t) {
    replace(t, "Max. number of dynamics            :   3",
            "Max. number of dynamics            :   4");
  });
  expect_error([&] { read_parrec_header(dynamics); }, {"'dynamic scan number'", "is 4"});
  // Versions other than 4, 4.1 and 4.2 are refused, naming the version.
  const fs::path version = edited_copy(dir, par, rec, [](std::string& t) {
    replace(t, "image export tool     V4.2", "image export tool     V3");
  });
  expect_error([&] { read_parrec_header(version); },
               {"edited.PAR", "version 'V3'", "not supported"});
  // A slice property that varies (nibabel reads one value for the series).
  const fs::path varying = edited_copy(dir, par, rec, [](std::string& t) {
    replace(t, "\n  2   1    1  1 0 2     1  16 ", "\n  2   1    1  1 0 2     1   8 ");
  });
  expect_error([&] { read_parrec_header(varying); }, {"image pixel size", "varies"});
  // No REC beside the PAR.
  const test::TempDir lonely;
  fs::copy_file(par, lonely / "lonely.PAR");
  expect_error([&] { read_parrec_header(lonely / "lonely.PAR"); }, {"lonely.REC"});
  EXPECT_FALSE(detail::is_parrec_header("\x89HDF\r\n"));
  EXPECT_TRUE(detail::is_parrec_header(test::read_bytes(par).substr(0, 64)));
}

}  // namespace
}  // namespace imx
