#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::expect_error;
using test::TempDir;

TEST(ReadVolume, MissingFileNamesIt) {
  TempDir dir;
  expect_error([&] { read_volume(dir / "nothing.nrrd"); }, {"nothing.nrrd", "no such file"});
  expect_error([&] { read_volume(dir / "nothing.nii.gz"); }, {"nothing.nii.gz", "no such file"});
}

TEST(ReadVolume, UnknownExtensionListsTheSupportedOnes) {
  TempDir dir;
  test::write_bytes(dir / "scan.vtk", "not a volume");
  expect_error([&] { read_volume(dir / "scan.vtk"); },
               {"scan.vtk", ".vtk", ".nrrd", ".nhdr", ".nii", ".nii.gz"});
  test::write_bytes(dir / "scan.gz", "x");
  expect_error([&] { read_volume(dir / "scan.gz"); }, {"scan.gz", ".nii.gz"});
}

TEST(ReadVolume, AFolderIsReadAsDicomAndAnEmptyOneSaysSo) {
  TempDir dir;
  std::filesystem::create_directory(dir / "d.nrrd");
  expect_error([&] { read_volume(dir / "d.nrrd"); }, {"d.nrrd", "no DICOM image"});
}

TEST(ReadVolume, ExtensionsAreCaseInsensitive) {
  TempDir dir;
  VolumeData v = make_phantom("cube", 8);
  write_nrrd(v, dir / "c.nrrd");
  std::filesystem::rename(dir / "c.nrrd", dir / "C.NRRD");
  EXPECT_EQ(read_volume(dir / "C.NRRD").dims, v.dims);
}

}  // namespace
}  // namespace imx
