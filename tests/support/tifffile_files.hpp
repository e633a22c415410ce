// Small TIFF, BigTIFF, ImageJ and OME-TIFF files written by tifffile (Debian's /usr/bin/python3,
// python3-tifffile; LZW by Pillow, as Debian's tifffile has no imagecodecs to encode it), with
// tifffile's own reading of each as the reference: a snippet writes files and calls ref(...)
// for the voxels a test checks.
#pragma once
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "temp_dir.hpp"

namespace imx::test {

// Whether /usr/bin/python3 has tifffile, numpy and Pillow (checked once).
inline bool have_tifffile() {
  static const bool ok =
      std::system("/usr/bin/python3 -c 'import tifffile, numpy, PIL' >/dev/null 2>&1") == 0;
  return ok;
}

// Prepended to every snippet: ref(file, array) writes an array as little-endian float64 (C
// order) for the C++ side to compare with (tifffile.imwrite writes grey pages unless told);
// pil_stack(name, array, compression) writes a 3-D array page by page with Pillow (through
// libtiff).
inline const char* kTifffilePrelude = R"PY(
import os, struct, sys
import numpy as np
import tifffile
from PIL import Image

# Grey pages unless a test says otherwise: tifffile takes a first axis of 3 or 4 for colour.
_imwrite = tifffile.imwrite
def _grey_imwrite(*args, **kwargs):
    kwargs.setdefault('photometric', 'minisblack')
    return _imwrite(*args, **kwargs)
tifffile.imwrite = _grey_imwrite

def ref(file, array):
    np.asarray(array, dtype='<f8').tofile(file)

def pil_stack(name, array, compression):
    pages = [Image.fromarray(np.ascontiguousarray(p)) for p in array]
    pages[0].save(name, save_all=True, append_images=pages[1:], compression=compression)

def patch(name, offset, fmt, value):
    with open(name, 'r+b') as f:
        f.seek(offset)
        f.write(struct.pack(fmt, value))

def tag_value_at(name, page, tag):
    """The file offset of a tag's value (inline in the IFD entry for small values)."""
    with tifffile.TiffFile(name) as t:
        return t.pages[page].tags[tag].valueoffset
)PY";

// Runs the prelude and `snippet` in `dir`; false (with the script's output as a test failure)
// when Python fails.
inline bool run_tifffile_python(const TempDir& dir, const std::string& snippet) {
  write_bytes(dir / "make.py", std::string(kTifffilePrelude) + snippet);
  const std::string command =
      "cd '" + dir.path().string() + "' && /usr/bin/python3 make.py >make.log 2>&1";
  if (std::system(command.c_str()) == 0) return true;
  ADD_FAILURE() << "tifffile script failed:\n" << read_bytes(dir / "make.log");
  return false;
}

}  // namespace imx::test

// Skips the running test where tifffile is missing.
#define SKIP_WITHOUT_TIFFFILE()      \
  if (!::imx::test::have_tifffile()) \
  GTEST_SKIP() << "/usr/bin/python3 with tifffile, numpy and Pillow is not available"
