// Streamlines as the reference reads them (nibabel.streamlines.load for .trk and .tck; for what
// nibabel does not read, .tck of float64 and .tsf, a numpy parse that splits the values at their
// NaN records), written by a test's Python snippet as FILE.ref and compared with what intermix
// reads.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <glm/vec3.hpp>

#include "intermix/streamlines.hpp"
#include "nibabel_reference.hpp"

namespace imx::test {

// Prepended to the tests' snippets (after kNibabelPrelude). write_ref(out, streamlines, dpp,
// dps) writes: streamline count, point count, each length (int64), the points (RAS, float64),
// then per-point and per-streamline arrays (count, then name length, UTF-8 name, values as
// float64); a name of k > 1 columns becomes "name[0]" .. "name[k-1]", names are stripped.
inline const char* kStreamlinesPrelude = R"PY(
import struct
from nibabel.streamlines import Tractogram
from nibabel.streamlines.trk import header_2_dtype

def write_ref(out, streamlines, dpp, dps):
    streamlines = [np.asarray(s, np.float64).reshape(-1, 3) for s in streamlines]
    lengths = np.array([len(s) for s in streamlines], '<i8')
    pts = np.concatenate(streamlines) if streamlines else np.zeros((0, 3))
    def arrays(d, rows):
        items = []
        for name, a in d.items():
            a = np.asarray(a, np.float64).reshape(rows, -1)
            for j in range(a.shape[1]):
                items.append((name.strip() + (f'[{j}]' if a.shape[1] > 1 else ''), a[:, j]))
        return items
    with open(out, 'wb') as f:
        np.array([len(lengths), lengths.sum()], '<i8').tofile(f)
        lengths.tofile(f)
        pts.astype('<f8').tofile(f)
        for items in (arrays(dpp, len(pts)), arrays(dps, len(lengths))):
            np.array([len(items)], '<i8').tofile(f)
            for name, values in items:
                b = name.encode('utf-8')
                np.array([len(b)], '<i8').tofile(f)
                f.write(b)
                values.astype('<f8').tofile(f)

# What nibabel.streamlines.load reads from `path`, as write_ref's `out` (default path + '.ref').
def ref(path, out=None):
    t = nib.streamlines.load(path).tractogram
    dpp = {k: t.data_per_point[k].get_data() for k in t.data_per_point}
    dps = {k: t.data_per_streamline[k] for k in t.data_per_streamline}
    write_ref(out or path + '.ref', list(t.streamlines), dpp, dps)

# An MRtrix track file's records (width values each) split at all-NaN records, up to an
# all-infinite one: the parse that nibabel has no equivalent of for .tsf and float64.
def mrtrix_runs(path, width):
    data = open(path, 'rb').read()
    head = data[:data.index(b'\nEND\n')].decode()
    fields = dict(l.split(':', 1) for l in head.split('\n')[1:] if ':' in l)
    dtype = {'Float32LE': '<f4', 'Float32BE': '>f4', 'Float64LE': '<f8',
             'Float64BE': '>f8'}[fields['datatype'].strip()]
    offset = int(fields['file'].split()[1])
    values = np.frombuffer(data[offset:], dtype)
    records = values[:len(values) // width * width].astype(np.float64).reshape(-1, width)
    runs, start = [], 0
    for i, r in enumerate(records):
        if np.isnan(r).all():
            if i > start:
                runs.append(records[start:i])
            start = i + 1
        elif np.isinf(r).all():
            break
    return runs

# Writes an MRtrix track file of `runs` (arrays of width columns) as `dtype` ('<f4', '>f8', ...):
# magic, `fields`, the data after a NaN record per run, then an inf record when `end`.
def write_mrtrix(path, magic, runs, dtype, width, fields=None, end=True):
    name = {'<f4': 'Float32LE', '>f4': 'Float32BE', '<f8': 'Float64LE', '>f8': 'Float64BE'}[dtype]
    body = b''.join(np.concatenate([np.asarray(r, np.float64).reshape(-1, width),
                                    np.full((1, width), np.nan)]).astype(dtype).tobytes()
                    for r in runs)
    if end:
        body += np.full(width, np.inf).astype(dtype).tobytes()
    lines = [magic] + [f'{k}: {v}' for k, v in (fields or {}).items()] + [f'datatype: {name}']
    offset = 0
    while True:
        head = ('\n'.join(lines + [f'file: . {offset}', 'END']) + '\n').encode()
        if len(head) == offset:
            break
        offset = len(head)
    open(path, 'wb').write(head + body)
)PY";

struct StreamlinesReference {
  std::vector<int64_t> lengths;
  std::vector<glm::dvec3> points;  // RAS mm
  std::vector<std::pair<std::string, std::vector<double>>> point_values, streamline_values;
};

inline StreamlinesReference read_streamlines_reference(const std::filesystem::path& ref) {
  const std::string bytes = read_bytes(ref);
  StreamlinesReference r;
  size_t at = 0;
  bool ok = true;
  auto take = [&](void* out, size_t n) {
    if (!ok || at + n > bytes.size()) {
      ok = false;
      return;
    }
    std::memcpy(out, bytes.data() + at, n);
    at += n;
  };
  auto int64 = [&] {
    int64_t v = 0;
    take(&v, sizeof v);
    return v;
  };
  const int64_t count = int64(), total = int64();
  if (!ok || count < 0 || total < 0 || uint64_t(count) > bytes.size() ||
      uint64_t(total) > bytes.size()) {
    ADD_FAILURE() << "no reference in " << ref;
    return r;
  }
  r.lengths.resize(size_t(count));
  take(r.lengths.data(), 8 * r.lengths.size());
  r.points.resize(size_t(total));
  take(r.points.data(), 24 * r.points.size());
  for (auto* arrays : {&r.point_values, &r.streamline_values}) {
    const int64_t n = int64();
    for (int64_t i = 0; ok && i < n; ++i) {
      std::string name(size_t(std::max<int64_t>(0, std::min<int64_t>(int64(), 1000))), '\0');
      take(name.data(), name.size());
      std::vector<double> values(arrays == &r.point_values ? r.points.size() : r.lengths.size());
      take(values.data(), 8 * values.size());
      arrays->emplace_back(std::move(name), std::move(values));
    }
  }
  EXPECT_TRUE(ok && at == bytes.size()) << "malformed reference " << ref;
  return r;
}

// The reference's streamlines that intermix keeps: 2 points or more, every coordinate finite.
inline std::vector<bool> kept_by_intermix(const StreamlinesReference& r) {
  std::vector<bool> keep(r.lengths.size());
  size_t at = 0;
  for (size_t i = 0; i < r.lengths.size(); ++i) {
    bool finite = true;
    for (int64_t k = 0; k < r.lengths[i]; ++k, ++at)
      for (int c = 0; c < 3; ++c)
        finite = finite && std::isfinite(static_cast<float>(r.points[at][c]));
    keep[i] = r.lengths[i] >= 2 && finite;
  }
  return keep;
}

inline const std::vector<float>* find_values(const std::vector<StreamlineValues>& arrays,
                                             const std::string& name) {
  for (const StreamlineValues& a : arrays)
    if (a.name == name) return &a.values;
  return nullptr;
}

// `s` holds the reference's streamlines (less those intermix drops), every point within 1e-4 mm
// once RAS is made LPS, and every named array's values.
inline void expect_streamlines_match(const Streamlines& s, const StreamlinesReference& r,
                                     const std::string& what) {
  const std::vector<bool> keep = kept_by_intermix(r);
  ASSERT_EQ(s.offsets.size(), s.count() + 1) << what;
  ASSERT_EQ(s.offsets.back(), s.points.size()) << what;
  ASSERT_EQ(s.count(), static_cast<size_t>(std::count(keep.begin(), keep.end(), true))) << what;
  ASSERT_EQ(s.point_values.size(), r.point_values.size()) << what;
  ASSERT_EQ(s.streamline_values.size(), r.streamline_values.size()) << what;
  for (const auto& [name, values] : r.point_values) {
    const std::vector<float>* got = find_values(s.point_values, name);
    ASSERT_NE(got, nullptr) << what << ": no point values named '" << name << "'";
    ASSERT_EQ(got->size(), s.points.size()) << what << ": " << name;
  }
  for (const auto& [name, values] : r.streamline_values) {
    const std::vector<float>* got = find_values(s.streamline_values, name);
    ASSERT_NE(got, nullptr) << what << ": no streamline values named '" << name << "'";
    ASSERT_EQ(got->size(), s.count()) << what << ": " << name;
  }
  int wrong = 0;
  const auto same = [](double want, float got) {
    return static_cast<float>(want) == got || (std::isnan(want) && std::isnan(got));
  };
  size_t ref_point = 0, out = 0;
  for (size_t i = 0; i < r.lengths.size(); ++i) {
    const auto n = static_cast<size_t>(r.lengths[i]);
    if (!keep[i]) {
      ref_point += n;
      continue;
    }
    ASSERT_EQ(s.length(out), n) << what << ": streamline " << i;
    for (size_t k = 0; k < n; ++k) {
      const glm::dvec3 want = r.points[ref_point + k] * glm::dvec3(-1, -1, 1);
      const glm::vec3 got = s.points[s.offsets[out] + k];
      for (int c = 0; c < 3; ++c)
        if (!(std::abs(got[c] - want[c]) <= 1e-4) && wrong++ < 5)
          ADD_FAILURE() << what << ": streamline " << i << " point " << k << " axis " << c << " is "
                        << got[c] << ", the reference (LPS) " << want[c];
      for (const auto& [name, values] : r.point_values) {
        const float got_value = (*find_values(s.point_values, name))[s.offsets[out] + k];
        if (!same(values[ref_point + k], got_value) && wrong++ < 5)
          ADD_FAILURE() << what << ": '" << name << "' of streamline " << i << " point " << k
                        << " is " << got_value << ", the reference " << values[ref_point + k];
      }
    }
    for (const auto& [name, values] : r.streamline_values) {
      const float got_value = (*find_values(s.streamline_values, name))[out];
      if (!same(values[i], got_value) && wrong++ < 5)
        ADD_FAILURE() << what << ": '" << name << "' of streamline " << i << " is " << got_value
                      << ", the reference " << values[i];
    }
    ref_point += n;
    ++out;
  }
  EXPECT_EQ(wrong, 0) << what << ": values differing from the reference";
}

// Whether one of `notes` holds `part`.
inline bool has_note(const std::vector<std::string>& notes, const std::string& part) {
  for (const std::string& n : notes)
    if (n.find(part) != std::string::npos) return true;
  return false;
}

}  // namespace imx::test
