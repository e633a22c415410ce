// DICOM reading on small series written here with GDCM: rescale and types, geometry (tilt,
// uneven spacing), SUV, and one clear error for each kind of bad input.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gdcmDataElement.h>
#include <gdcmFragment.h>
#include <gdcmItem.h>
#include <gdcmSequenceOfFragments.h>
#include <gdcmSequenceOfItems.h>
#include <gdcmWriter.h>
#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "expect_error.hpp"
#include "gdcm_elements.hpp"
#include "intermix/dicom.hpp"
#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "io/dicom/dicom_suv.hpp"
#include "io/dicom/dicom_tags.hpp"
#include "io/streams/gzip.hpp"
#include "linear_time.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::expect_error;
using test::put_text;
using test::put_us;
using test::TempDir;

struct Slice {
  std::string series_uid = "1.2.3.4";
  int series_number = 1;
  std::string sop_uid;  // default: from the file name
  std::string modality = "CT";
  std::string photometric = "MONOCHROME2";
  int samples = 1;
  int rows = 4, columns = 3;
  glm::dvec3 position{0.0};
  std::string orientation = "1\\0\\0\\0\\1\\0";
  std::string spacing = "0.5\\0.8";  // between rows, between columns
  std::string slope = "1", intercept = "0";
  std::vector<int16_t> pixels;  // rows * columns; default: 10 * index + slice-independent
  bool pixel_data = true;
  int bits_stored = 16, high_bit = 15, pixel_representation = 1;
  std::string window_center, window_width;
  bool pet = false;  // add PET SUV tags
  std::string pet_units = "BQML";
  bool pet_weight = true;
  int instance_number = 0;                    // 0: no InstanceNumber
  std::function<void(gdcm::DataSet&)> extra;  // further tags
  gdcm::TransferSyntax::TSType syntax = gdcm::TransferSyntax::ExplicitVRLittleEndian;
};

void write_slice(const fs::path& file, const Slice& s) {
  gdcm::Writer w;
  gdcm::DataSet& ds = w.GetFile().GetDataSet();
  const std::string sop =
      s.sop_uid.empty()
          ? fmt::format("1.2.3.4.5.{}",
                        std::hash<std::string>()(file.filename().string()) % 100000000)
          : s.sop_uid;
  put_text(ds, 0x0008, 0x0016, gdcm::VR::UI,
           s.pet ? "1.2.840.10008.5.1.4.1.1.128" : "1.2.840.10008.5.1.4.1.1.2");
  put_text(ds, 0x0008, 0x0018, gdcm::VR::UI, sop);
  put_text(ds, 0x0008, 0x0060, gdcm::VR::CS, s.modality);
  put_text(ds, 0x0008, 0x103e, gdcm::VR::LO, "SYNTHETIC");
  put_text(ds, 0x0020, 0x000e, gdcm::VR::UI, s.series_uid);
  put_text(ds, 0x0020, 0x0011, gdcm::VR::IS, std::to_string(s.series_number));
  put_text(ds, 0x0020, 0x0032, gdcm::VR::DS,
           fmt::format("{}\\{}\\{}", s.position.x, s.position.y, s.position.z));
  put_text(ds, 0x0020, 0x0037, gdcm::VR::DS, s.orientation);
  put_us(ds, 0x0028, 0x0002, static_cast<uint16_t>(s.samples));
  put_text(ds, 0x0028, 0x0004, gdcm::VR::CS, s.photometric);
  put_us(ds, 0x0028, 0x0010, static_cast<uint16_t>(s.rows));
  put_us(ds, 0x0028, 0x0011, static_cast<uint16_t>(s.columns));
  put_text(ds, 0x0028, 0x0030, gdcm::VR::DS, s.spacing);
  put_us(ds, 0x0028, 0x0100, 16);
  put_us(ds, 0x0028, 0x0101, static_cast<uint16_t>(s.bits_stored));
  put_us(ds, 0x0028, 0x0102, static_cast<uint16_t>(s.high_bit));
  put_us(ds, 0x0028, 0x0103, static_cast<uint16_t>(s.pixel_representation));
  put_text(ds, 0x0028, 0x1052, gdcm::VR::DS, s.intercept);
  put_text(ds, 0x0028, 0x1053, gdcm::VR::DS, s.slope);
  if (!s.window_center.empty()) {
    put_text(ds, 0x0028, 0x1050, gdcm::VR::DS, s.window_center);
    put_text(ds, 0x0028, 0x1051, gdcm::VR::DS, s.window_width);
  }
  if (s.pet) {
    put_text(ds, 0x0054, 0x1001, gdcm::VR::CS, s.pet_units);
    put_text(ds, 0x0054, 0x1102, gdcm::VR::CS, "START");
    if (s.pet_weight) put_text(ds, 0x0010, 0x1030, gdcm::VR::DS, "70");
    put_text(ds, 0x0008, 0x0031, gdcm::VR::TM, "110000");
    put_text(ds, 0x0008, 0x0032, gdcm::VR::TM, "110500");
    gdcm::Item item;
    gdcm::DataSet& nested = item.GetNestedDataSet();
    put_text(nested, 0x0018, 0x1072, gdcm::VR::TM, "100000.00");
    put_text(nested, 0x0018, 0x1074, gdcm::VR::DS, "370000000");
    put_text(nested, 0x0018, 0x1075, gdcm::VR::DS, "6586.2");
    gdcm::SmartPointer<gdcm::SequenceOfItems> sq = new gdcm::SequenceOfItems;
    sq->SetLengthToUndefined();
    sq->AddItem(item);
    gdcm::DataElement de(gdcm::Tag(0x0054, 0x0016));
    de.SetVR(gdcm::VR::SQ);
    de.SetValue(*sq);
    de.SetVLToUndefined();
    ds.Replace(de);
  }
  if (s.instance_number > 0)
    put_text(ds, 0x0020, 0x0013, gdcm::VR::IS, std::to_string(s.instance_number));
  if (s.extra) s.extra(ds);
  if (s.pixel_data) {
    std::vector<int16_t> px = s.pixels;
    const size_t n = static_cast<size_t>(s.rows) * s.columns * s.samples;
    if (px.empty())
      for (size_t i = 0; i < n; ++i) px.push_back(static_cast<int16_t>(10 * i));
    gdcm::DataElement de(gdcm::Tag(0x7fe0, 0x0010));
    de.SetVR(gdcm::VR::OW);
    de.SetByteValue(reinterpret_cast<const char*>(px.data()), static_cast<uint32_t>(px.size() * 2));
    ds.Replace(de);
  }
  w.GetFile().GetHeader().SetDataSetTransferSyntax(s.syntax);
  w.SetFileName(file.c_str());
  ASSERT_TRUE(w.Write()) << file;
}

// Slices at the given positions along z, named s0.dcm, s1.dcm, ...
void write_series(const TempDir& dir, const std::vector<double>& z, Slice base = {}) {
  for (size_t i = 0; i < z.size(); ++i) {
    base.position = glm::dvec3(-10, 20, z[i]);
    write_slice(dir / fmt::format("s{}.dcm", i), base);
  }
}

TEST(DicomSynthetic, BitsOutsideBitsStoredAreIgnoredAndTheSignExtended) {
  // 12 of 16 bits: the top four hold an overlay's garbage, bit 11 is the sign when signed.
  auto values = [](int bits_stored, int high_bit, int representation,
                   std::vector<uint16_t> stored) {
    TempDir dir;
    Slice s;
    s.rows = 2;
    s.columns = 2;
    s.bits_stored = bits_stored;
    s.high_bit = high_bit;
    s.pixel_representation = representation;
    for (uint16_t v : stored) s.pixels.push_back(static_cast<int16_t>(v));
    write_series(dir, {0.0, 2.0}, s);
    VolumeData v = read_dicom(dir.path()).volume;
    return std::vector<double>{v.value_at(0, 0, 0), v.value_at(1, 0, 0), v.value_at(0, 1, 0),
                               v.value_at(1, 1, 0)};
  };
  EXPECT_EQ(values(12, 11, 1, {0xF7FF, 0x0800, 0xA001, 0x5FFF}),
            (std::vector<double>{2047, -2048, 1, -1}));
  EXPECT_EQ(values(12, 11, 0, {0xF7FF, 0x0800, 0xA001, 0x5FFF}),
            (std::vector<double>{2047, 2048, 1, 4095}));
  // High bit 15: the stored bits are the top twelve, the low four are dropped.
  EXPECT_EQ(values(12, 15, 1, {0x7FF3, 0x8000, 0x001F, 0xFFF0}),
            (std::vector<double>{2047, -2048, 1, -1}));
}

TEST(DicomSynthetic, RescaledIntegersGetTheSmallestType) {
  TempDir dir;
  Slice s;
  s.intercept = "-1024";
  write_series(dir, {0, 2, 4}, s);
  DicomVolume d = read_dicom(dir.path());
  EXPECT_EQ(d.volume.type(), VoxelType::i16);
  EXPECT_EQ(d.volume.dims, glm::ivec3(3, 4, 3));
  EXPECT_DOUBLE_EQ(d.volume.value_at(2, 1, 0), 10.0 * 5 - 1024);
  // Spacing: PixelSpacing is between rows (j) then columns (i).
  EXPECT_DOUBLE_EQ(d.volume.spacing().x, 0.8);
  EXPECT_DOUBLE_EQ(d.volume.spacing().y, 0.5);
  EXPECT_NEAR(d.volume.spacing().z, 2.0, 1e-12);
  EXPECT_EQ(glm::dvec3(d.volume.index_to_world[3]), glm::dvec3(-10, 20, 0));

  TempDir small;
  write_series(small, {0, 1});  // 0..110
  EXPECT_EQ(read_dicom(small.path()).volume.type(), VoxelType::u8);
}

TEST(DicomSynthetic, FractionalOrDifferingSlopesGiveFloat) {
  TempDir dir;
  Slice s;
  s.slope = "0.5";
  write_series(dir, {0, 1}, s);
  DicomVolume d = read_dicom(dir.path());
  EXPECT_EQ(d.volume.type(), VoxelType::f32);
  EXPECT_DOUBLE_EQ(d.volume.value_at(1, 0, 1), 5.0);

  TempDir mixed;
  Slice a, b;
  b.slope = "2";
  a.position = glm::dvec3(0, 0, 0);
  b.position = glm::dvec3(0, 0, 1);
  write_slice(mixed / "a.dcm", a);
  write_slice(mixed / "b.dcm", b);
  DicomVolume m = read_dicom(mixed.path());
  EXPECT_EQ(m.volume.type(), VoxelType::f32);
  EXPECT_DOUBLE_EQ(m.volume.value_at(1, 0, 0), 10.0);
  EXPECT_DOUBLE_EQ(m.volume.value_at(1, 0, 1), 20.0);  // its own slope
}

TEST(DicomSynthetic, SlicesAreSortedByPositionNotFileName) {
  TempDir dir;
  for (int i = 0; i < 3; ++i) {
    Slice s;
    s.position = glm::dvec3(0, 0, 10.0 - 5.0 * i);  // s0 is the highest
    s.pixels.assign(12, static_cast<int16_t>(i));
    write_slice(dir / fmt::format("s{}.dcm", i), s);
  }
  DicomVolume d = read_dicom(dir.path());
  EXPECT_EQ(d.volume.value_at(0, 0, 0), 2.0);  // the lowest slice first
  EXPECT_EQ(d.volume.value_at(0, 0, 2), 0.0);
  EXPECT_NEAR(d.volume.index_to_world[3].z, 0.0, 1e-12);
}

TEST(DicomSynthetic, EvenTiltIsAShearWithoutResampling) {
  TempDir dir;
  for (int i = 0; i < 4; ++i) {
    Slice s;
    s.orientation = "1\\0\\0\\0\\0.8\\-0.6";     // columns tilted about x
    s.position = glm::dvec3(1, 2, 3 + 2.0 * i);  // stacked along z, not along the normal
    write_slice(dir / fmt::format("s{}.dcm", i), s);
  }
  DicomVolume d = read_dicom(dir.path());
  EXPECT_EQ(d.volume.dims.z, 4);
  EXPECT_EQ(d.volume.type(), VoxelType::u8);  // not resampled
  const glm::dmat4& m = d.volume.index_to_world;
  EXPECT_LT(glm::length(glm::dvec3(m[2]) - glm::dvec3(0, 0, 2)), 1e-9);
  EXPECT_LT(glm::length(glm::dvec3(m[1]) - 0.5 * glm::dvec3(0, 0.8, -0.6)), 1e-9);
  // Voxel (i, j, k) at IPP_k + i dcol row + j drow col.
  glm::dvec3 w(m * glm::dvec4(2, 3, 1, 1));
  EXPECT_LT(glm::length(w - (glm::dvec3(1, 2, 5) + 2 * 0.8 * glm::dvec3(1, 0, 0) +
                             3 * 0.5 * glm::dvec3(0, 0.8, -0.6))),
            1e-9);
}

TEST(DicomSynthetic, UnevenSpacingIsResampledWithLinearBlends) {
  TempDir dir;
  const std::vector<double> z = {0, 1, 2, 4, 6};
  for (size_t i = 0; i < z.size(); ++i) {
    Slice s;
    s.position = glm::dvec3(0, 0, z[i]);
    s.pixels.assign(12, static_cast<int16_t>(100 * i));
    write_slice(dir / fmt::format("s{}.dcm", i), s);
  }
  DicomVolume d = read_dicom(dir.path());
  ASSERT_EQ(d.volume.dims.z, 7);  // 1 mm, the smallest gap
  EXPECT_EQ(d.volume.type(), VoxelType::f32);
  const double expected[] = {0, 100, 200, 250, 300, 350, 400};  // z = 3 and 5 are blends
  for (int k = 0; k < 7; ++k) EXPECT_NEAR(d.volume.value_at(1, 2, k), expected[k], 1e-4) << k;
  ASSERT_FALSE(d.notes.empty());
  EXPECT_NE(d.notes.back().find("gaps from 1 to 2 mm"), std::string::npos) << d.notes.back();

  DicomReadOptions coarse;
  coarse.slice_spacing_mm = 1.5;  // 6 mm in 4 steps of 1.5
  DicomVolume c = read_dicom(dir.path(), coarse);
  ASSERT_EQ(c.volume.dims.z, 5);
  EXPECT_NEAR(c.volume.value_at(0, 0, 1), 150.0, 1e-4);  // z 1.5
  EXPECT_NEAR(c.volume.value_at(0, 0, 3), 325.0, 1e-4);  // z 4.5
  EXPECT_NEAR(c.volume.spacing().z, 1.5, 1e-12);
}

TEST(DicomSynthetic, WindowAndUnits) {
  TempDir dir;
  Slice s;
  s.window_center = "40\\50";
  s.window_width = "400\\500";
  write_series(dir, {0, 1}, s);
  DicomVolume d = read_dicom(dir.path());
  ASSERT_TRUE(d.window.has_value());
  EXPECT_EQ(*d.window, glm::dvec2(40, 400));
  EXPECT_EQ(d.units, "HU");
}

TEST(DicomSynthetic, SuvByBodyWeightWithDecayCorrection) {
  TempDir dir;
  Slice s;
  s.modality = "PT";
  s.pet = true;
  write_series(dir, {0, 3}, s);
  DicomVolume bq = read_dicom(dir.path());
  EXPECT_EQ(bq.units, "BQML");
  DicomReadOptions o;
  o.units = "suv";
  DicomVolume suv = read_dicom(dir.path(), o);
  EXPECT_EQ(suv.units, "g/ml");
  // 70 kg, 370 MBq injected at 10:00, half-life 6586.2 s, series at 11:00.
  const double factor = 70000.0 / (370e6 * std::pow(2.0, -3600.0 / 6586.2));
  EXPECT_NEAR(suv.volume.value_at(2, 3, 1), bq.volume.value_at(2, 3, 1) * factor,
              1e-6 * bq.volume.value_at(2, 3, 1) * factor);
  EXPECT_EQ(suv.volume.type(), VoxelType::f32);

  detail::DicomSuvTags tags;
  tags.units = "BQML";
  tags.weight_kg = 80;
  tags.has_radiopharmaceutical = true;
  tags.total_dose_bq = 400e6;
  tags.half_life_s = 6586.2;
  tags.start_time_s = 23 * 3600.0 + 30 * 60;  // injected before midnight
  tags.series_time_s = 0.5 * 3600;
  EXPECT_NEAR(detail::suv_body_weight_factor(tags, "x"),
              80000.0 / (400e6 * std::pow(2.0, -3600.0 / 6586.2)), 1e-12);
  tags.decay_correction = "ADMIN";
  EXPECT_NEAR(detail::suv_body_weight_factor(tags, "x"), 80000.0 / 400e6, 1e-15);
}

TEST(DicomSynthetic, SuvErrorsNameTheMissingTag) {
  TempDir ct;
  write_series(ct, {0, 1});
  DicomReadOptions o;
  o.units = "suv";
  expect_error([&] { read_dicom(ct.path(), o); }, {"suv", "Units (0054,1001)"});
  TempDir pet;
  Slice s;
  s.modality = "PT";
  s.pet = true;
  s.pet_weight = false;
  write_series(pet, {0, 1}, s);
  expect_error([&] { read_dicom(pet.path(), o); }, {"PatientWeight (0010,1030)"});
  o.units = "percent";
  expect_error([&] { read_dicom(pet.path(), o); }, {"units 'percent'"});
}

// --- bad input: one clear error each --------------------------------------------------------

TEST(DicomErrors, FolderWithoutDicom) {
  TempDir dir;
  test::write_bytes(dir / "readme.txt", "not an image\n");
  test::write_bytes(dir / "fake.dcm", std::string(300, 'x'));
  fs::create_directories(dir / "empty");
  expect_error([&] { read_dicom(dir.path()); }, {dir.path().string(), "no DICOM image files"});
  expect_error([&] { read_dicom(dir / "fake.dcm"); }, {"fake.dcm", "not a DICOM file"});
  expect_error([&] { read_dicom(dir / "nothing"); }, {"no such file or folder"});
}

TEST(DicomErrors, TwoSeriesAndAnAmbiguousChoice) {
  TempDir dir;
  Slice a, b;
  b.series_uid = "1.2.3.99";  // same SeriesNumber 1, another series
  for (int i = 0; i < 3; ++i) {
    a.position.z = i;
    write_slice(dir / fmt::format("a{}.dcm", i), a);
  }
  for (int i = 0; i < 2; ++i) {
    b.position.z = i;
    write_slice(dir / fmt::format("b{}.dcm", i), b);
  }
  ASSERT_EQ(list_dicom_series(dir.path()).size(), 2u);
  DicomReadOptions o;
  o.series = "1";
  expect_error([&] { read_dicom(dir.path(), o); }, {"series '1' is ambiguous", "matches 2"});
  o.series = "7";
  expect_error([&] { read_dicom(dir.path(), o); }, {"no series '7'", "1 'SYNTHETIC' CT 3x4"});
  o.series = "1.2.3.99";  // by UID
  EXPECT_EQ(read_dicom(dir.path(), o).volume.dims.z, 2);
  DicomVolume largest = read_dicom(dir.path());
  EXPECT_EQ(largest.volume.dims.z, 3);
  ASSERT_FALSE(largest.notes.empty());
  EXPECT_NE(largest.notes.front().find("of 2 series"), std::string::npos);
}

TEST(DicomErrors, LocalizerAndOtherOrientationAreSeriesOfTheirOwn) {
  TempDir dir;
  write_series(dir, {0, 1, 2, 3});
  Slice sagittal;
  sagittal.orientation = "0\\1\\0\\0\\0\\-1";
  write_slice(dir / "sag.dcm", sagittal);
  std::vector<DicomSeriesInfo> list = list_dicom_series(dir.path());
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].id, "1.1");
  EXPECT_EQ(list[0].slices, 4);
  EXPECT_EQ(list[1].id, "1.2");
  EXPECT_EQ(read_dicom(dir.path()).volume.dims.z, 4);  // the largest
}

TEST(DicomErrors, MissingSlice) {
  TempDir dir;
  write_series(dir, {0, 2, 4, 8, 10});
  expect_error([&] { read_dicom(dir.path()); }, {"missing slice", "4.000 mm", "s2.dcm", "s3.dcm"});
}

TEST(DicomErrors, DuplicatePositions) {
  TempDir dir;
  write_series(dir, {0, 2, 4});
  Slice again;
  again.position = glm::dvec3(-10, 20, 2);
  write_slice(dir / "copy.dcm", again);
  expect_error([&] { read_dicom(dir.path()); },
               {"do not form whole volumes", "holds 1 image where", "holds 2"});
}

TEST(DicomErrors, NoPixelData) {
  TempDir dir;
  Slice s;
  s.pixel_data = false;
  write_slice(dir / "empty.dcm", s);
  expect_error([&] { read_dicom(dir / "empty.dcm"); }, {"empty.dcm", "no pixel data (7FE0,0010)"});
}

TEST(DicomErrors, TruncatedSlice) {
  TempDir dir;
  Slice s;
  s.rows = s.columns = 64;
  write_series(dir, {0, 1, 2}, s);
  std::string bytes = test::read_bytes(dir / "s1.dcm");
  test::write_bytes(dir / "s1.dcm", bytes.substr(0, bytes.size() - 3000));
  expect_error([&] { read_dicom(dir.path()); }, {"s1.dcm"});
  // Cut inside the header, too: refused as unreadable.
  test::write_bytes(dir / "s1.dcm", bytes.substr(0, 200));
  expect_error([&] { read_dicom(dir.path()); }, {"s1.dcm", "cannot be read"});
  // Cut before its preamble, it cannot be known as DICOM: the gap it leaves names it.
  TempDir five;
  write_series(five, {0, 1, 2, 3, 4}, s);
  test::write_bytes(five / "s2.dcm", bytes.substr(0, 100));
  expect_error([&] { read_dicom(five.path()); },
               {"missing slice", "1 file in the folder is not a DICOM image", "s2.dcm"});
}

TEST(DicomErrors, UnsupportedPhotometricInterpretation) {
  TempDir dir;
  Slice s;
  s.photometric = "RGB";
  s.samples = 3;
  write_slice(dir / "colour.dcm", s);
  // RGB reads as colour from 8-bit samples (dicom_colour_test.cpp); 16-bit ones are refused.
  expect_error([&] { read_dicom(dir / "colour.dcm"); },
               {"colour.dcm", "unsupported RGB image", "BitsAllocated 16"});
  Slice p;
  p.photometric = "PALETTE COLOR";
  write_slice(dir / "palette.dcm", p);
  expect_error([&] { read_dicom(dir / "palette.dcm"); },
               {"unsupported photometric interpretation 'PALETTE COLOR'"});
}

TEST(DicomErrors, GarbageAfterAValidPreambleDoesNotCrash) {
  TempDir dir;
  std::string bytes(128, '\0');
  bytes += "DICM";
  for (int i = 0; i < 2000; ++i) bytes.push_back(static_cast<char>((i * 7919) % 251));
  test::write_bytes(dir / "x.dcm", bytes);
  expect_error([&] { read_dicom(dir / "x.dcm"); }, {"x.dcm"});
}

TEST(DicomErrors, MalformedElementsAreRefusedBeforeGdcmParsesThem) {
  TempDir dir;
  // A bare data set whose first element's length is cut short (GDCM asserts on it).
  test::write_bytes(dir / "short.dcm", std::string("\x08\x00\x08\x26UR\x00\x00", 8));
  expect_error([&] { read_dicom(dir / "short.dcm"); }, {"short.dcm", "cannot be read"});
  // A valid slice followed by an element that claims 4 GB (GDCM would allocate it).
  write_slice(dir / "big.dcm", Slice{});
  std::string bytes = test::read_bytes(dir / "big.dcm");
  bytes += std::string("\xe1\x7f\x10\x00OB\x00\x00\x00\x00\x00\xf0", 12);
  test::write_bytes(dir / "big.dcm", bytes);
  expect_error([&] { read_dicom(dir / "big.dcm"); }, {"big.dcm", "claims"});
  // A folder of only such files says why, rather than "no DICOM files".
  expect_error([&] { list_dicom_series(dir.path()); }, {"cannot be read"});
}

// Values that are present but unusable are errors that quote them, never a default in silence
// (a NaN slope read as 1, a zero pixel spacing as 1 mm, a NaN intercept as 0).
TEST(DicomErrors, PresentButUnusableValuesAreQuotedNotTakenForMissing) {
  auto error_with = [](auto change, std::initializer_list<std::string> fragments) {
    TempDir dir;
    Slice s;
    change(s);
    write_series(dir, {0, 2}, s);
    expect_error([&] { read_dicom(dir.path()); }, fragments);
  };
  for (const char* slope : {"NaN", "1e400", "word", "0"})
    error_with([&](Slice& s) { s.slope = slope; },
               {"s0.dcm", "RescaleSlope (0028,1053) is present but unusable",
                std::string("'") + slope + "'"});
  error_with([](Slice& s) { s.intercept = "NaN"; },
             {"RescaleIntercept (0028,1052) is present but unusable: 'NaN'"});
  for (const char* spacing : {"0\\0", "NaN\\1", "-1\\-1", "0.5"})
    error_with([&](Slice& s) { s.spacing = spacing; },
               {"PixelSpacing (0028,0030) is present but unusable"});
  error_with([](Slice& s) { s.orientation = "1\\0\\0\\0\\x\\0"; },
             {"ImageOrientationPatient (0020,0037) is present but unusable"});
  error_with([](Slice& s) { s.orientation = "0\\0\\0\\0\\1\\0"; },
             {"ImageOrientationPatient (0020,0037) is present but unusable: '0\\0\\0\\0\\1\\0'"});
  // A value that is not text is shown escaped.
  error_with([](Slice& s) { s.slope = std::string("1\x01", 2); }, {"'1\\x01'"});
  // A usable slope that makes the stored values too large for a float: refused, not +-inf.
  for (const char* slope : {"1e38", "-1e38"})
    error_with([&](Slice& s) { s.slope = slope; },
               {"s", ".dcm: RescaleSlope (0028,1053)", "beyond what a float holds"});
}

TEST(DicomErrors, TheListingNamesTheFilesThatReadingWouldRefuse) {
  TempDir dir;
  write_series(dir, {0, 1, 2});
  Slice bad;
  bad.slope = "NaN";
  bad.position = glm::dvec3(-10, 20, 3);
  write_slice(dir / "s3.dcm", bad);
  std::vector<std::string> refused;
  const std::vector<DicomSeriesInfo> series = list_dicom_series(dir.path(), &refused);
  ASSERT_EQ(series.size(), 1u);
  EXPECT_EQ(series.front().slices, 3);
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_NE(refused.front().find("s3.dcm: RescaleSlope"), std::string::npos) << refused.front();
  expect_error([&] { read_dicom(dir.path()); }, {"s3.dcm", "RescaleSlope"});
  // A folder named like a volume file says so.
  TempDir parent;
  std::filesystem::create_directory(parent / "x.nrrd");
  expect_error([&] { read_volume(parent / "x.nrrd"); }, {"x.nrrd: a folder, not a '.nrrd' file"});
}

TEST(DicomErrors, DifferentPixelSpacingsAreQuotedAsTheFilesSayThem) {
  TempDir dir;
  Slice a, b;
  a.spacing = "0.5\\0.5";
  b.spacing = "0.7\\0.7";
  b.position = glm::dvec3(0, 0, 1);
  write_slice(dir / "a.dcm", a);
  write_slice(dir / "b.dcm", b);
  expect_error([&] { read_dicom(dir.path()); },
               {"has PixelSpacing 0.7\\0.7, but", "a.dcm has PixelSpacing 0.5\\0.5"});
  // A slice without the tag has none (it was quoted as "1\\1", the spacing assumed for it).
  Slice none = a;
  none.extra = [](gdcm::DataSet& ds) { ds.Remove(gdcm::Tag(0x0028, 0x0030)); };
  write_slice(dir / "a.dcm", none);
  b.spacing = "1\\1";
  write_slice(dir / "b.dcm", b);
  expect_error([&] { read_dicom(dir.path()); }, {"no PixelSpacing", "PixelSpacing 1\\1"});
}

TEST(DicomErrors, ASingleSliceNeedsAUsableThicknessOrSaysItAssumedOne) {
  for (const char* thickness : {"0", "NaN", "-5"}) {
    TempDir dir;
    Slice s;
    s.extra = [&](gdcm::DataSet& ds) { put_text(ds, 0x0018, 0x0050, gdcm::VR::DS, thickness); };
    write_slice(dir / "one.dcm", s);
    expect_error([&] { read_dicom(dir.path()); },
                 {"one.dcm", "SliceThickness (0018,0050) is present but unusable"});
  }
  TempDir dir;
  write_slice(dir / "one.dcm", Slice{});
  const DicomVolume d = read_dicom(dir.path());
  EXPECT_NEAR(d.volume.spacing().z, 1.0, 1e-12);
  ASSERT_FALSE(d.notes.empty());
  EXPECT_NE(d.notes.back().find("placed 1 mm thick"), std::string::npos) << d.notes.back();
  // A usable spacing wins over an unusable one, and a stack needs neither.
  TempDir both;
  Slice t;
  t.extra = [](gdcm::DataSet& ds) {
    put_text(ds, 0x0018, 0x0088, gdcm::VR::DS, "0");
    put_text(ds, 0x0018, 0x0050, gdcm::VR::DS, "2.5");
  };
  write_slice(both / "one.dcm", t);
  EXPECT_NEAR(read_dicom(both.path()).volume.spacing().z, 2.5, 1e-12);
  t.extra = [](gdcm::DataSet& ds) { put_text(ds, 0x0018, 0x0050, gdcm::VR::DS, "NaN"); };
  TempDir stack;
  write_series(stack, {0, 3}, t);
  EXPECT_NEAR(read_dicom(stack.path()).volume.spacing().z, 3.0, 1e-12);
}

TEST(DicomErrors, PixelDataMustHoldExactlyTheFramesTheHeaderSays) {
  TempDir dir;
  Slice longer;
  longer.pixels.assign(4 * 3 * 6, 7);  // six frames' worth under no NumberOfFrames
  write_slice(dir / "long.dcm", longer);
  expect_error([&] { read_dicom(dir / "long.dcm"); },
               {"long.dcm", "pixel data holds 144 bytes", "give 24"});
  for (const char* frames : {"NaN", "many", "2.5", "0"}) {
    Slice s;
    s.extra = [&](gdcm::DataSet& ds) { put_text(ds, 0x0028, 0x0008, gdcm::VR::IS, frames); };
    write_slice(dir / "frames.dcm", s);
    expect_error([&] { read_dicom(dir / "frames.dcm"); },
                 {"frames.dcm", "NumberOfFrames (0028,0008) is present but unusable"});
  }
  // Six frames said and held: read, stacked by their spacing, which they cannot do without.
  Slice six = longer;
  six.extra = [](gdcm::DataSet& ds) { put_text(ds, 0x0028, 0x0008, gdcm::VR::IS, "6"); };
  write_slice(dir / "six.dcm", six);
  expect_error([&] { read_dicom(dir / "six.dcm"); },
               {"six.dcm", "no SpacingBetweenSlices (0018,0088) or SliceThickness (0018,0050)"});
  six.extra = [](gdcm::DataSet& ds) {
    put_text(ds, 0x0028, 0x0008, gdcm::VR::IS, "6");
    put_text(ds, 0x0018, 0x0088, gdcm::VR::DS, "1.5");
  };
  write_slice(dir / "six.dcm", six);
  const VolumeData v = read_dicom(dir / "six.dcm").volume;
  EXPECT_EQ(v.dims, glm::ivec3(3, 4, 6));
  EXPECT_NEAR(v.spacing().z, 1.5, 1e-12);
}

// A lossless JPEG stream whose frame header claims 255-bit samples: one error naming the file and
// the syntax (crashing streams are in DicomData.CompressedMutants* and IsolatedCall.*).
TEST(DicomErrors, ACorruptCompressedStreamIsAnErrorNamingItsSyntax) {
  const std::string jpeg(
      "\xff\xd8"                                              // SOI
      "\xff\xc3\x00\x0b\xff\x00\x04\x00\x03\x01\x01\x11\x00"  // SOF3: 255 bits, 4 x 3
      "\xff\xd9",                                             // EOI
      17);
  TempDir dir;
  Slice s;
  s.syntax = gdcm::TransferSyntax::JPEGLosslessProcess14_1;
  s.pixel_data = false;
  s.extra = [&](gdcm::DataSet& ds) {
    gdcm::SmartPointer<gdcm::SequenceOfFragments> fragments = new gdcm::SequenceOfFragments;
    gdcm::Fragment fragment;
    std::string padded = jpeg + std::string(jpeg.size() % 2, '\0');
    fragment.SetByteValue(padded.data(), static_cast<uint32_t>(padded.size()));
    fragments->AddFragment(fragment);
    gdcm::DataElement de(gdcm::Tag(0x7fe0, 0x0010));
    de.SetValue(*fragments);
    de.SetVLToUndefined();  // GDCM asserts when the VR is set first
    de.SetVR(gdcm::VR::OB);
    ds.Replace(de);
  };
  write_slice(dir / "bad.jpeg.dcm", s);
  expect_error([&] { read_dicom(dir / "bad.jpeg.dcm"); },
               {"bad.jpeg.dcm", "1.2.840.10008.1.2.4.70 (JPEG Lossless", "corrupt"});
  // The listing decodes compressed files, so it names the one reading would refuse.
  write_series(dir, {1, 2});
  std::vector<std::string> refused;
  ASSERT_EQ(list_dicom_series(dir.path(), &refused).size(), 1u);
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_NE(refused.front().find("bad.jpeg.dcm"), std::string::npos) << refused.front();
  EXPECT_NE(refused.front().find("corrupt"), std::string::npos) << refused.front();
}

TEST(DicomErrors, ATransferSyntaxThatDoesNotMatchThePixelDataIsRefused) {
  for (auto syntax :
       {gdcm::TransferSyntax::JPEGBaselineProcess1, gdcm::TransferSyntax::JPEGLosslessProcess14_1,
        gdcm::TransferSyntax::JPEG2000Lossless, gdcm::TransferSyntax::RLELossless}) {
    TempDir dir;
    Slice s;
    s.syntax = syntax;
    write_slice(dir / "relabelled.dcm", s);
    expect_error([&] { read_dicom(dir / "relabelled.dcm"); },
                 {"relabelled.dcm", "says the pixel data is compressed, but it is a plain value"});
  }
}

}  // namespace
}  // namespace imx

namespace imx {
namespace {

// Volumes of `positions` slices each: pixel value 100 * volume + 10 * slice, files named
// v{volume}_s{slice}.dcm, instance numbers volume-major; `tag` adds each image's own tags.
void write_volumes(const TempDir& dir, int volumes, int positions,
                   const std::function<void(gdcm::DataSet&, int volume, int slice)>& tag = {}) {
  for (int v = 0; v < volumes; ++v)
    for (int z = 0; z < positions; ++z) {
      Slice s;
      s.modality = "MR";
      s.position = glm::dvec3(0, 0, 2.0 * z);
      s.instance_number = 1 + v * positions + z;
      s.pixels.assign(12, static_cast<int16_t>(100 * v + 10 * z));
      if (tag) s.extra = [&, v, z](gdcm::DataSet& ds) { tag(ds, v, z); };
      write_slice(dir / fmt::format("v{}_s{}.dcm", v, z), s);
    }
}

void put_fd(gdcm::DataSet& ds, uint16_t g, uint16_t e, std::vector<double> v) {
  gdcm::DataElement de(gdcm::Tag(g, e));
  de.SetVR(gdcm::VR::FD);
  de.SetByteValue(reinterpret_cast<const char*>(v.data()), static_cast<uint32_t>(v.size() * 8));
  ds.Replace(de);
}

// Each frame k holds volume `expected[k]`: slice z has value 100 * volume + 10 * z.
void expect_frames(const fs::path& dir, const std::vector<int>& expected) {
  const VolumeHeader h = read_dicom_header(dir);
  ASSERT_EQ(h.frames, static_cast<int>(expected.size()));
  for (size_t f = 0; f < expected.size(); ++f) {
    DicomReadOptions o;
    o.frame = static_cast<int>(f);
    const DicomVolume d = read_dicom(dir, o);
    for (int z = 0; z < d.volume.dims.z; ++z)
      EXPECT_EQ(d.volume.value_at(1, 1, z), 100 * expected[f] + 10 * z) << "frame " << f;
  }
}

TEST(DicomVolumes, ClassicTimeSeriesSplitsInInstanceOrder) {
  TempDir dir;
  write_volumes(dir, 4, 3);
  expect_frames(dir.path(), {0, 1, 2, 3});
  DicomReadOptions o;
  o.frame = 4;
  expect_error([&] { read_dicom(dir.path(), o); }, {"frame 4", "4 frames (0 to 3)"});
  EXPECT_NE(read_dicom(dir.path()).notes.back().find("frame 0 of 4"), std::string::npos);
}

TEST(DicomVolumes, TemporalPositionOutranksInstanceNumbers) {
  TempDir dir;
  // Instance numbers that run backwards: without the temporal positions, the volumes reverse.
  write_volumes(dir, 3, 2, [](gdcm::DataSet& ds, int v, int z) {
    put_text(ds, 0x0020, 0x0013, gdcm::VR::IS, std::to_string(100 - 2 * v - z));
  });
  expect_frames(dir.path(), {2, 1, 0});
  write_volumes(dir, 3, 2, [](gdcm::DataSet& ds, int v, int z) {
    put_text(ds, 0x0020, 0x0013, gdcm::VR::IS, std::to_string(100 - 2 * v - z));
    put_text(ds, 0x0020, 0x0100, gdcm::VR::IS, std::to_string(v + 1));
  });
  expect_frames(dir.path(), {0, 1, 2});
}

TEST(DicomVolumes, SliceTimingInTriggerTimeDoesNotSplitVolumes) {
  TempDir dir;
  write_volumes(dir, 2, 3, [](gdcm::DataSet& ds, int, int z) {
    put_text(ds, 0x0018, 0x1060, gdcm::VR::DS, std::to_string(100 * z));  // one per slice
  });
  expect_frames(dir.path(), {0, 1});
}

TEST(DicomVolumes, DiffusionLabelsAndRepeatedB0) {
  TempDir dir;
  const double b[] = {0, 1000, 0};
  write_volumes(dir, 3, 2, [&](gdcm::DataSet& ds, int v, int) {
    put_fd(ds, 0x0018, 0x9087, {b[v]});
    if (b[v] > 0) put_fd(ds, 0x0018, 0x9089, {0.0, 0.6, 0.8});
  });
  expect_frames(dir.path(), {0, 1, 2});
  const VolumeHeader h = read_dicom_header(dir.path());
  ASSERT_EQ(h.frame_labels.size(), 3u);
  EXPECT_EQ(h.frame_labels[1].b_value, 1000.0);
  ASSERT_TRUE(h.frame_labels[1].b_vector.has_value());
  EXPECT_NEAR(h.frame_labels[1].b_vector->y, 0.6, 1e-9);  // columns run along +y
  EXPECT_NEAR(h.frame_labels[1].b_vector->z, 0.8, 1e-9);
  EXPECT_EQ(h.frame_labels[2].b_value, 0.0);
  EXPECT_EQ(*h.frame_labels[2].b_vector, glm::dvec3(0.0));
}

TEST(DicomVolumes, AnIncompleteVolumeIsRefusedNamingTheFiles) {
  TempDir dir;
  write_volumes(dir, 2, 3);
  fs::remove(dir / "v1_s2.dcm");
  expect_error([&] { read_dicom(dir.path()); },
               {"5 images at 3 slice positions", "do not form whole volumes", "v0_s2.dcm"});
}

TEST(DicomVolumes, OneUidUnderTwoSeriesNumbersIsTwoSeries) {
  TempDir dir;
  Slice a;
  for (int n = 1; n <= 2; ++n)
    for (int z = 0; z < 3; ++z) {
      a.series_number = n;
      a.position.z = z;
      write_slice(dir / fmt::format("n{}_{}.dcm", n, z), a);
    }
  const std::vector<DicomSeriesInfo> list = list_dicom_series(dir.path());
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].id, "1");
  EXPECT_EQ(list[1].id, "2");
  EXPECT_EQ(read_dicom(dir.path()).frames, 1);
}

// A Siemens mosaic of 3 tiles of 2x2 in a 4x4 image (2 per row), rows x columns swapped to tell
// them apart: tile t holds 10 * t + pixel.
void write_mosaic(const fs::path& file, bool with_count) {
  Slice s;
  s.modality = "MR";
  s.rows = 4;
  s.columns = 4;
  s.spacing = "2\\3";  // between rows 2 mm, between columns 3 mm
  s.position = glm::dvec3(100, 200, 300);
  s.pixels.assign(16, 0);
  for (int t = 0; t < 4; ++t)
    for (int p = 0; p < 4; ++p)
      s.pixels[static_cast<size_t>((t / 2 * 2 + p / 2) * 4 + t % 2 * 2 + p % 2)] =
          static_cast<int16_t>(t < 3 ? 10 * t + p : -1);
  s.extra = [with_count](gdcm::DataSet& ds) {
    put_text(ds, 0x0008, 0x0008, gdcm::VR::CS, "ORIGINAL\\PRIMARY\\M\\ND\\MOSAIC");
    put_text(ds, 0x0018, 0x0088, gdcm::VR::DS, "5");
    put_text(ds, 0x0019, 0x0010, gdcm::VR::LO, "SIEMENS MR HEADER");
    if (with_count) put_us(ds, 0x0019, 0x100a, 3);
  };
  write_slice(file, s);
}

TEST(DicomVolumes, MosaicTilesAreSlicesPlacedFromTheMosaicCorner) {
  TempDir dir;
  write_mosaic(dir / "m.dcm", true);
  const DicomVolume d = read_dicom(dir / "m.dcm");
  ASSERT_EQ(d.volume.dims, glm::ivec3(2, 2, 3));
  for (int t = 0; t < 3; ++t)
    for (int p = 0; p < 4; ++p) EXPECT_EQ(d.volume.value_at(p % 2, p / 2, t), 10 * t + p);
  // The first tile's corner pixel lies half the size difference (1 tile) in from the mosaic's.
  const glm::dvec3 origin(d.volume.index_to_world[3]);
  EXPECT_NEAR(glm::length(origin - glm::dvec3(103, 202, 300)), 0.0, 1e-9);
  EXPECT_NEAR(glm::length(glm::dvec3(d.volume.index_to_world[2]) - glm::dvec3(0, 0, 5)), 0.0, 1e-9);
  write_mosaic(dir / "m.dcm", false);  // no count, no CSA header: refused, never a 2-D slice
  expect_error([&] { read_dicom(dir / "m.dcm"); }, {"m.dcm", "mosaic", "NumberOfImagesInMosaic"});
}

TEST(DicomVolumes, GeReversedPolarityRowsAreMirrored) {
  TempDir dir;
  auto pepolar = [](const std::string& user_data) {
    return [user_data](gdcm::DataSet& ds) {
      put_text(ds, 0x0019, 0x0010, gdcm::VR::LO, "GEMS_ACQU_01");
      put_text(ds, 0x0019, 0x109c, gdcm::VR::LO, "epi_pepolar");
      put_text(ds, 0x0019, 0x10b3, gdcm::VR::DS, user_data);
    };
  };
  Slice s;
  s.extra = pepolar("1");
  write_slice(dir / "r.dcm", s);
  const DicomVolume d = read_dicom(dir / "r.dcm");
  // Default pixels are 10 * index: row r of the file lands on row 3 - r.
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(d.volume.value_at(c, 3 - r, 0), 10 * (r * 3 + c));
  s.extra = pepolar("0");  // forward: as stored
  write_slice(dir / "r.dcm", s);
  EXPECT_EQ(read_dicom(dir / "r.dcm").volume.value_at(0, 0, 0), 0);
  // Alternating, without a temporal position to tell the polarities apart: as stored, as
  // dcm2niix reads it (dicom_diffusion_test.cpp checks the split by temporal position).
  s.extra = pepolar("2");
  write_slice(dir / "r.dcm", s);
  const DicomVolume alternating = read_dicom(dir / "r.dcm");
  EXPECT_EQ(alternating.volume.value_at(0, 0, 0), 0);
  EXPECT_TRUE(std::any_of(alternating.notes.begin(), alternating.notes.end(),
                          [](const std::string& n) { return n.find("epi_pepolar") != n.npos; }));
}

}  // namespace
}  // namespace imx

namespace imx {
namespace {

TEST(DicomVolumes, GzipCompressedFilesReadAsTheirContentAndErrorsNameThem) {
  TempDir plain, packed;
  write_volumes(plain, 2, 3);
  for (const auto& e : fs::directory_iterator(plain.path())) {
    const std::string cmd = fmt::format("gzip -c '{}' > '{}.gz'", e.path().string(),
                                        (packed / e.path().filename()).string());
    ASSERT_EQ(std::system(cmd.c_str()), 0);
  }
  expect_frames(packed.path(), {0, 1});
  const DicomVolume single = read_dicom(packed / "v1_s0.dcm.gz");
  EXPECT_EQ(single.volume.value_at(0, 0, 0), 100);
  // A corrupt member: refused, naming the .gz file, not a temporary copy.
  std::string bytes;
  {
    std::ifstream in(packed / "v0_s1.dcm.gz", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  bytes[bytes.size() / 2] ^= 0x55;
  std::ofstream(packed / "v0_s1.dcm.gz", std::ios::binary) << bytes;
  expect_error([&] { read_dicom(packed.path()); }, {(packed / "v0_s1.dcm.gz").string()});
  try {
    read_dicom(packed.path());
  } catch (const std::exception& e) {
    EXPECT_EQ(std::string(e.what()).find("intermix-dcmgz"), std::string::npos) << e.what();
  }
}

// A .dcm.gz is inflated to a temporary file no larger than the memory budget (it could not be
// read past it): 8 MiB of zeros in 8 KB under a 4 MiB budget were written out whole, up to
// 4 GiB whatever the budget (issue 48, item 2).
TEST(DicomVolumes, AGzipFileIsInflatedNoFurtherThanTheBudget) {
  TempDir dir;
  const std::string zeros(size_t{8} << 20, '\0');
  std::ostringstream packed;
  detail::gzip(std::span(reinterpret_cast<const uint8_t*>(zeros.data()), zeros.size()), packed, 9,
               "test");
  test::write_bytes(dir / "big.dcm.gz", packed.str());
  set_input_limits({uint64_t{4} << 20, false});
  const std::string message = expect_error([&] { read_dicom(dir / "big.dcm.gz"); },
                                           {"big.dcm.gz", "memory budget of 4.0 MiB"});
  set_input_limits({});
  EXPECT_EQ(message.find("not a DICOM file"), std::string::npos) << message;
}

}  // namespace
}  // namespace imx

namespace imx {
namespace {

TEST(DicomVolumes, TheSameImageTwiceIsRefusedNotASecondVolume) {
  TempDir dir;
  write_volumes(dir, 1, 3);
  fs::create_directory(dir / "copy");
  for (int z = 0; z < 3; ++z)
    fs::copy_file(dir / fmt::format("v0_s{}.dcm", z), dir / "copy" / fmt::format("v0_s{}.dcm", z));
  expect_error([&] { read_dicom(dir.path()); }, {"are the same image", "SOPInstanceUID"});
}

// No image with a position: stacked as dcm2niix stacks them, one volume, with a note
// (dicom_diffusion_test.cpp compares the placement with dcm2niix's); some with and some without
// one: refused.
TEST(DicomVolumes, ImagesWithoutPositionsAreStackedAsOneVolume) {
  TempDir dir;
  for (int i = 0; i < 3; ++i) {
    Slice s;
    s.extra = [](gdcm::DataSet& ds) { ds.Remove(gdcm::Tag(0x0020, 0x0032)); };
    write_slice(dir / fmt::format("p{}.dcm", i), s);
  }
  const DicomVolume d = read_dicom(dir.path());
  EXPECT_EQ(d.frames, 1);
  EXPECT_EQ(d.volume.dims.z, 3);
  EXPECT_TRUE(std::any_of(d.notes.begin(), d.notes.end(), [](const std::string& n) {
    return n.find("no ImagePositionPatient") != n.npos;
  }));
  Slice placed;
  placed.position = glm::dvec3(0, 0, 7);
  write_slice(dir / "p3.dcm", placed);
  expect_error([&] { read_dicom(dir.path()); }, {"no ImagePositionPatient"});
}

// A DICOM text value's padding is trimmed in linear time (issue 48, item 3): the leading spaces
// of a value were erased one at a time, each moving the rest of the value, so that 256 KiB of
// them took far longer than 16 values of 16 KiB. Values are read whole from a file of any size;
// 256 KiB is far more than any real one.
TEST(DicomTags, TextValuesAreTrimmedInLinearTime) {
  auto data_set = [](size_t padding) {
    gdcm::DataSet ds;
    put_text(ds, 0x0028, 0x1053, gdcm::VR::DS, std::string(padding, ' ') + "1.5\\2.5");
    return ds;
  };
  const gdcm::DataSet full = data_set(size_t{256} << 10), part = data_set(size_t{16} << 10);
  auto read = [&](const std::string& which) {
    const std::vector<double> v =
        detail::tag_numbers(which == "full" ? full : part, 0x0028, 0x1053);
    EXPECT_EQ(v, (std::vector<double>{1.5, 2.5}));
  };
  EXPECT_LE(test::growth_over_linear(read, "full", "part"), test::kMaxGrowthOverLinear)
      << "time(n) / (16 time(n/16))";
}

}  // namespace
}  // namespace imx
