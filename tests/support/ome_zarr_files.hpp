// Small OME-Zarr (NGFF 0.4, Zarr v2) images written by zarr-python 2 and numcodecs (Debian's
// /usr/bin/python3), with zarr's own reading of each as the reference: a test's snippet calls
// image(...) for each image and ref(...) for the voxels it checks.
#pragma once
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "temp_dir.hpp"

namespace imx::test {

// Whether /usr/bin/python3 has zarr, numcodecs and numpy (checked once).
inline bool have_zarr() {
  static const bool ok =
      std::system("/usr/bin/python3 -c 'import zarr, numcodecs, numpy' >/dev/null 2>&1") == 0;
  return ok;
}

// Prepended to every snippet: image(name, levels, axes, ...) writes an OME-Zarr group `name`
// whose levels are the numpy arrays `levels` (scales and translations per level, in axis order),
// and returns the arrays; ref(file, array) writes zarr's reading of an array as little-endian
// float64 (C order) for the C++ side to compare with.
inline const char* kZarrPrelude = R"PY(
import json, os, sys, zlib
import numpy as np
import zarr, numcodecs
from numcodecs import Blosc, GZip, Zlib, Zstd

def image(name, levels, axes='zyx', chunks=None, compressor=None, fill_value=0, separator='.',
          scales=None, translations=None, ms_scale=None, dtype=None, write=None):
    store = zarr.DirectoryStore(name, dimension_separator=separator)
    root = zarr.group(store=store, overwrite=True)
    datasets = []
    arrays = []
    for i, data in enumerate(levels):
        a = root.create_dataset(str(i), shape=data.shape, dtype=dtype or data.dtype,
                                chunks=chunks[i] if chunks else None, compressor=compressor,
                                fill_value=fill_value, dimension_separator=separator)
        if write is None:
            a[...] = data
        else:
            write(a, data)
        arrays.append(a)
        ct = []
        if scales:
            ct.append({'type': 'scale', 'scale': scales[i]})
        if translations:
            ct.append({'type': 'translation', 'translation': translations[i]})
        if not ct:
            ct = [{'type': 'scale', 'scale': [1.0] * data.ndim}]
        datasets.append({'path': str(i), 'coordinateTransformations': ct})
    kinds = {'t': 'time', 'c': 'channel', 'z': 'space', 'y': 'space', 'x': 'space'}
    ms = {'version': '0.4', 'name': name,
          'axes': [{'name': n, 'type': kinds[n]} for n in axes], 'datasets': datasets}
    if ms_scale:
        ms['coordinateTransformations'] = [{'type': 'scale', 'scale': ms_scale}]
    root.attrs['multiscales'] = [ms]
    return arrays

def ref(file, array):
    np.asarray(array, dtype='<f8').tofile(file)
)PY";

// Runs the prelude and `snippet` in `dir`; false (with the script's output as a test failure)
// when Python fails.
inline bool run_zarr_python(const TempDir& dir, const std::string& snippet) {
  write_bytes(dir / "make.py", std::string(kZarrPrelude) + snippet);
  const std::string command =
      "cd '" + dir.path().string() + "' && /usr/bin/python3 make.py >make.log 2>&1";
  if (std::system(command.c_str()) == 0) return true;
  ADD_FAILURE() << "zarr script failed:\n" << read_bytes(dir / "make.log");
  return false;
}

}  // namespace imx::test

// Skips the running test where zarr-python is missing.
#define SKIP_WITHOUT_ZARR()      \
  if (!::imx::test::have_zarr()) \
  GTEST_SKIP() << "/usr/bin/python3 with zarr and numcodecs is not available"
