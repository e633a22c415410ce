// Small DICOM series written by pydicom (Debian's /usr/bin/python3) from the pixels of a real MR
// slice of the shared data, and dcm2niix's conversion of them: the reference the DICOM reader's
// vendor tags (diffusion, derived images, placement) are checked against. A test's snippet calls
// write(...) for each file; dcm2niix() then converts the folder as `dcm2niix -b y -z n`.
#pragma once
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx::test {

// The slice whose pixels the series are made of.
inline std::filesystem::path pydicom_source_slice() {
  return shared_data("dicom/ts/1.dcm");
}

// Whether /usr/bin/python3 has pydicom and numpy (checked once).
inline bool have_pydicom() {
  static const bool ok =
      std::system("/usr/bin/python3 -c 'import pydicom, numpy' >/dev/null 2>&1") == 0;
  return ok;
}

// Whether pydicom is there and dcm2niix is on PATH (checked once).
inline bool have_pydicom_and_dcm2niix() {
  static const bool ok = have_pydicom() && std::system("dcm2niix -h >/dev/null 2>&1") == 0;
  return ok;
}

// Prepended to every snippet: write(path, rows, cols, position, orientation, pixels, series_uid,
// instance, extra) writes one MR slice (explicit VR little endian, u16), `extra(ds)` adding or
// removing tags; pixels(rows, cols, scale) is the source slice, every fifth pixel, scaled;
// rotated_axial(deg) an axial ImageOrientationPatient turned in plane; positions(orientation, n,
// step) n slice positions along row x column.
inline const char* kPydicomPrelude = R"PY(
import math, os, sys
import numpy as np
import pydicom
from pydicom.dataset import FileDataset, FileMetaDataset
from pydicom.uid import ExplicitVRLittleEndian, generate_uid

_base = pydicom.dcmread(sys.argv[1]).pixel_array.astype(np.float64)

def pixels(rows, cols, scale):
    return np.clip(_base[::5, ::5][:rows, :cols] * scale, 0, 32000).astype(np.uint16)

def rotated_axial(deg):
    a = math.radians(deg)
    return [math.cos(a), math.sin(a), 0.0, -math.sin(a), math.cos(a), 0.0]

def positions(orient, n, step, origin=(-40.0, -60.0, 10.0)):
    r = np.array(orient[:3]); c = np.array(orient[3:])
    return [np.array(origin) + np.cross(r, c) * step * s for s in range(n)]

def write(path, rows, cols, position, orient, px, series_uid, instance, extra=None,
          manufacturer='GE MEDICAL SYSTEMS'):
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = '1.2.840.10008.5.1.4.1.1.4'
    meta.MediaStorageSOPInstanceUID = generate_uid()
    meta.TransferSyntaxUID = ExplicitVRLittleEndian
    ds = FileDataset(path, {}, file_meta=meta, preamble=b'\0' * 128)
    ds.is_little_endian = True
    ds.is_implicit_VR = False
    ds.SOPClassUID = meta.MediaStorageSOPClassUID
    ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
    ds.ImageType = ['ORIGINAL', 'PRIMARY', 'OTHER']
    ds.Modality = 'MR'
    ds.Manufacturer = manufacturer
    ds.StudyInstanceUID = '1.2.826.0.1.3680043.8.498.1'
    ds.SeriesInstanceUID = series_uid
    ds.SeriesNumber = 5
    ds.SeriesDescription = 'SYNTH'
    ds.ProtocolName = 'SYNTH'
    ds.PatientName = 'Synth'
    ds.PatientID = 'synth'
    ds.PatientPosition = 'HFS'
    for tag in ('StudyDate', 'SeriesDate', 'AcquisitionDate'):
        setattr(ds, tag, '20240101')
    for tag in ('StudyTime', 'SeriesTime', 'AcquisitionTime'):
        setattr(ds, tag, '120000')
    ds.InstanceNumber = instance
    ds.EchoTime = 80
    ds.RepetitionTime = 4000
    ds.MagneticFieldStrength = 3
    ds.InPlanePhaseEncodingDirection = 'COL'
    if position is not None:
        ds.ImagePositionPatient = [float(round(v, 4)) for v in position]
    if orient is not None:
        ds.ImageOrientationPatient = [float(round(v, 6)) for v in orient]
    ds.PixelSpacing = [2.0, 2.5]
    ds.SliceThickness = 3.0
    ds.SpacingBetweenSlices = 3.0
    ds.SamplesPerPixel = 1
    ds.PhotometricInterpretation = 'MONOCHROME2'
    ds.Rows = rows
    ds.Columns = cols
    ds.BitsAllocated = 16
    ds.BitsStored = 16
    ds.HighBit = 15
    ds.PixelRepresentation = 0
    ds.RescaleIntercept = 0
    ds.RescaleSlope = 1
    if extra:
        extra(ds)
    if 'PixelData' not in ds:
        ds.PixelData = px.tobytes()
    ds.save_as(path, write_like_original=False)
)PY";

// Runs the prelude and `snippet` in `dir`; false (with the script's output as a test failure)
// when Python fails.
inline bool run_pydicom(const TempDir& dir, const std::string& snippet) {
  write_bytes(dir / "make.py", std::string(kPydicomPrelude) + snippet);
  const std::string command = "cd '" + dir.path().string() + "' && /usr/bin/python3 make.py '" +
                              pydicom_source_slice().string() + "' >make.log 2>&1";
  if (std::system(command.c_str()) == 0) return true;
  ADD_FAILURE() << "pydicom script failed:\n" << read_bytes(dir / "make.log");
  return false;
}

// dcm2niix's conversion of the folder `in` into `out`/`name`.nii (+ .json, .bval, .bvec as it
// writes them); its output goes to `out`/`name`.log. False (a test failure) when it fails.
inline bool run_dcm2niix(const std::filesystem::path& in, const std::filesystem::path& out,
                         const std::string& name) {
  std::filesystem::create_directories(out);
  const std::string log = (out / (name + ".log")).string();
  const std::string command = "dcm2niix -b y -z n -f '" + name + "' -o '" + out.string() + "' '" +
                              in.string() + "' >'" + log + "' 2>&1";
  if (std::system(command.c_str()) == 0) return true;
  ADD_FAILURE() << "dcm2niix failed:\n" << read_bytes(log);
  return false;
}

}  // namespace imx::test

// Skips the running test where pydicom, dcm2niix or the source slice is missing.
#define SKIP_WITHOUT_PYDICOM_AND_DCM2NIIX()      \
  SKIP_WITHOUT_SHARED_DATA("dicom/ts/1.dcm");    \
  if (!::imx::test::have_pydicom_and_dcm2niix()) \
  GTEST_SKIP() << "/usr/bin/python3 with pydicom, or dcm2niix, is not available"
