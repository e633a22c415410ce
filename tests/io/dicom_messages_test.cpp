// Issue 48's DICOM messages: each hostile input gets one line naming the file and the reason,
// never GDCM's text, and a file that cannot be opened is not taken for one that is no DICOM.
// The unreadable cases run `intermix` as another user where the tests run as root (whom no
// permission stops), and are skipped where that cannot be done.
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gdcmDataElement.h>
#include <gdcmWriter.h>
#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "expect_error.hpp"
#include "gdcm_elements.hpp"
#include "intermix/dicom.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::expect_error;
using test::put_text;
using test::put_us;
using test::TempDir;

struct Options {
  bool rows = true, columns = true, pixels = true;
  int rows_value = 4;
};

// A 3x4 CT slice at height z (explicit VR little endian, 16-bit), as `options` leaves it.
void write_slice(const fs::path& file, double z, const Options& options = {}) {
  gdcm::Writer w;
  gdcm::DataSet& ds = w.GetFile().GetDataSet();
  put_text(ds, 0x0008, 0x0016, gdcm::VR::UI, "1.2.840.10008.5.1.4.1.1.2");
  put_text(ds, 0x0008, 0x0018, gdcm::VR::UI, fmt::format("1.2.3.4.5.{}", static_cast<int>(z * 10)));
  put_text(ds, 0x0008, 0x0060, gdcm::VR::CS, "CT");
  put_text(ds, 0x0020, 0x000e, gdcm::VR::UI, "1.2.3.4");
  put_text(ds, 0x0020, 0x0011, gdcm::VR::IS, "1");
  put_text(ds, 0x0020, 0x0032, gdcm::VR::DS, fmt::format("0\\0\\{}", z));
  put_text(ds, 0x0020, 0x0037, gdcm::VR::DS, "1\\0\\0\\0\\1\\0");
  put_us(ds, 0x0028, 0x0002, 1);
  put_text(ds, 0x0028, 0x0004, gdcm::VR::CS, "MONOCHROME2");
  if (options.rows) put_us(ds, 0x0028, 0x0010, static_cast<uint16_t>(options.rows_value));
  if (options.columns) put_us(ds, 0x0028, 0x0011, 3);
  put_text(ds, 0x0028, 0x0030, gdcm::VR::DS, "0.5\\0.5");
  put_us(ds, 0x0028, 0x0100, 16);
  put_us(ds, 0x0028, 0x0101, 16);
  put_us(ds, 0x0028, 0x0102, 15);
  put_us(ds, 0x0028, 0x0103, 1);
  if (options.pixels) {
    std::vector<int16_t> px(12, 7);
    gdcm::DataElement de(gdcm::Tag(0x7fe0, 0x0010));
    de.SetVR(gdcm::VR::OW);
    de.SetByteValue(reinterpret_cast<const char*>(px.data()), static_cast<uint32_t>(px.size() * 2));
    ds.Replace(de);
  }
  w.GetFile().GetHeader().SetDataSetTransferSyntax(gdcm::TransferSyntax::ExplicitVRLittleEndian);
  w.SetFileName(file.c_str());
  ASSERT_TRUE(w.Write()) << file;
}

void write_series(const fs::path& folder, int slices) {
  fs::create_directories(folder);
  for (int i = 0; i < slices; ++i) write_slice(folder / fmt::format("s{}.dcm", i), i);
}

// `bytes` with its one occurrence of `from` replaced by `to` (of the same length).
std::string replaced(std::string bytes, const std::string& from, const std::string& to) {
  const size_t at = bytes.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  EXPECT_EQ(bytes.find(from, at + 1), std::string::npos) << from;
  if (at != std::string::npos) bytes.replace(at, from.size(), to);
  return bytes;
}

// What reading `path` throws, with what GDCM (or anything) printed on stderr meanwhile.
struct Refusal {
  std::string message, stderr_text;
};

Refusal refusal_of(const fs::path& path) {
  ::testing::internal::CaptureStderr();
  const std::string message = test::error_of([&] { read_dicom(path); });
  return {message, ::testing::internal::GetCapturedStderr()};
}

TEST(DicomMessages, AnUnknownOrMissingTransferSyntaxIsNamedWithoutGdcmText) {
  TempDir dir;
  write_slice(dir / "s.dcm", 0);
  const std::string bytes = test::read_bytes(dir / "s.dcm");
  // Same lengths, so the file meta group's length stays right.
  dir.write("unknown.dcm",
            replaced(bytes, std::string("1.2.840.10008.1.2.1\0", 20), "1.2.3.4.5.6.7.8.9.10"));
  dir.write("missing.dcm", replaced(bytes, std::string("\x02\x00\x10\x00UI", 6),
                                    std::string("\x02\x00\x11\x00UI", 6)));
  const Refusal unknown = refusal_of(dir / "unknown.dcm");
  EXPECT_EQ(unknown.message, (dir / "unknown.dcm").string() +
                                 ": unknown or unsupported transfer syntax "
                                 "'1.2.3.4.5.6.7.8.9.10' (0002,0010)");
  EXPECT_EQ(unknown.stderr_text, "");
  const Refusal missing = refusal_of(dir / "missing.dcm");
  EXPECT_EQ(missing.message, (dir / "missing.dcm").string() +
                                 ": no TransferSyntaxUID (0002,0010) in its file meta information");
  EXPECT_EQ(missing.stderr_text, "");
  // Through the command too, where the DICOMDIR check ran GDCM unquieted before.
  const test::CliResult r = test::run_cli("info " + (dir / "unknown.dcm").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.output, "intermix: error: " + unknown.message + "\n");
}

TEST(DicomMessages, AFileWithoutAnImageSaysWhichTagIsMissing) {
  TempDir dir;
  write_slice(dir / "no-rows.dcm", 0, {.rows = false});
  write_slice(dir / "no-size.dcm", 0, {.rows = false, .columns = false});
  write_slice(dir / "zero-rows.dcm", 0, {.rows_value = 0});
  EXPECT_EQ(
      test::error_of([&] { read_dicom(dir / "no-rows.dcm"); }),
      (dir / "no-rows.dcm").string() + ": a DICOM file without an image: no Rows (0028,0010)");
  EXPECT_EQ(test::error_of([&] { read_dicom(dir / "no-size.dcm"); }),
            (dir / "no-size.dcm").string() +
                ": a DICOM file without an image: no Rows (0028,0010) and no Columns (0028,0011)");
  EXPECT_EQ(
      test::error_of([&] { read_dicom(dir / "zero-rows.dcm"); }),
      (dir / "zero-rows.dcm").string() + ": a DICOM file without an image: Rows (0028,0010) is 0");
}

TEST(DicomMessages, AFileCutInItsMetaInformationSaysWhere) {
  TempDir dir;
  write_slice(dir / "s.dcm", 0);
  const std::string bytes = test::read_bytes(dir / "s.dcm");
  dir.write("cut.dcm", bytes.substr(0, 140));
  expect_error([&] { read_dicom(dir / "cut.dcm"); },
               {(dir / "cut.dcm").string() + ": a DICOM file that cannot be read (truncated or "
                                             "corrupt): file meta element (0002,0000) runs past "
                                             "the end of the file"});
  dir.write("short.dcm", bytes.substr(0, 134));  // the preamble and half an element
  expect_error([&] { read_dicom(dir / "short.dcm"); },
               {"short.dcm: a DICOM file that cannot be read (truncated or corrupt): the file "
                "ends after its file meta information"});
}

TEST(DicomMessages, TheListingRefusesAFileWithoutPixelDataAsReadingDoes) {
  TempDir dir;
  write_slice(dir / "empty.dcm", 0, {.pixels = false});
  std::vector<std::string> refused;
  ASSERT_EQ(list_dicom_series(dir / "empty.dcm", &refused).size(), 1u);
  const std::string read = test::error_of([&] { read_dicom(dir / "empty.dcm"); });
  EXPECT_EQ(read, (dir / "empty.dcm").string() + ": no pixel data (7FE0,0010) in this file");
  EXPECT_EQ(refused, std::vector<std::string>{read});
}

TEST(DicomMessages, AMissingPathSaysSoRatherThanListingFormats) {
  TempDir dir;
  write_slice(dir / "s.dcm", 0);
  for (const fs::path& path : {dir / "no-such-series", dir / "s.dcm" / "x"}) {
    const test::CliResult r = test::run_cli("info " + path.string());
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(r.output.rfind("intermix: error: " + path.string() + ": no such file or folder", 0),
              0u)
        << r.output;
    EXPECT_EQ(r.output.find("is not a format"), std::string::npos) << r.output;
  }
}

TEST(DicomMessages, ALinkToAFileThatIsNotThereSaysWhereItPoints) {
  TempDir dir;
  fs::create_symlink("gone.dcm", dir / "slice.dcm");
  const std::string expected =
      (dir / "slice.dcm").string() + ": a symbolic link to 'gone.dcm', which is not there";
  EXPECT_EQ(test::error_of([&] { read_dicom(dir / "slice.dcm"); }), expected);
  for (const std::string& command :
       {std::string("info "), "render -o " + (dir / "x.png").string() + " "}) {
    const test::CliResult r = test::run_cli(command + (dir / "slice.dcm").string());
    EXPECT_EQ(r.output, "intermix: error: " + expected + "\n") << command;
  }
}

// The shell prefix that runs a command as a user without root's permission override, or ""
// where the tests already run as one; nullopt where neither can be had.
std::optional<std::string> as_unprivileged_user() {
  if (::geteuid() != 0) return "";
  if (std::system("setpriv --version >/dev/null 2>&1") != 0) return std::nullopt;
  return "setpriv --reuid=65534 --regid=65534 --clear-groups ";
}

// info, render and convert of `source` as that user: each one line naming `named` and `reason`.
void expect_refused_as_user(const fs::path& source, const std::string& prefix,
                            const std::string& named, const std::string& reason,
                            const fs::path& out) {
  for (const std::string& command :
       std::vector<std::string>{"info ", "render -o " + (out / "x.png").string() + " ",
                                "convert -o " + (out / "x.nii").string() + " "}) {
    const test::CliResult r = test::run_cli(command + source.string(), prefix);
    SCOPED_TRACE(command);
    const bool listed = command == "info " && r.exit_code == 0;  // info lists what is refused
    if (listed) {
      EXPECT_NE(r.output.find("refused: " + named + ": " + reason), std::string::npos) << r.output;
      continue;
    }
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_NE(r.output.find(named + ": " + reason), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("not a DICOM"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("no DICOM image files"), std::string::npos) << r.output;
  }
}

TEST(DicomMessages, AFileOrFolderThatCannotBeReadSaysPermissionDenied) {
  const std::optional<std::string> prefix = as_unprivileged_user();
  if (!prefix) GTEST_SKIP() << "running as root without setpriv: no user that permissions stop";
  TempDir dir;
  fs::permissions(dir.path(), fs::perms::all);  // the other user reaches the cases
  const fs::path out = dir / "out";
  fs::create_directories(out);
  fs::permissions(out, fs::perms::all);
  // One slice of a series that cannot be read: it was "not a DICOM image, passed over".
  write_series(dir / "one", 4);
  fs::permissions(dir / "one" / "s2.dcm", fs::perms::none);
  expect_refused_as_user(dir / "one", *prefix, (dir / "one" / "s2.dcm").string(),
                         "cannot open the file: Permission denied", out);
  // A folder that cannot be listed: it was "no DICOM image files in this folder".
  write_series(dir / "locked", 2);
  fs::permissions(dir / "locked", fs::perms::none);
  expect_refused_as_user(dir / "locked", *prefix, (dir / "locked").string(),
                         "cannot read the folder: Permission denied", out);
  // A subfolder that cannot be listed: it was passed over without a word.
  write_series(dir / "outer" / "inner", 2);
  fs::permissions(dir / "outer" / "inner", fs::perms::none);
  expect_refused_as_user(dir / "outer", *prefix, (dir / "outer" / "inner").string(),
                         "cannot read the folder: Permission denied", out);
  for (const char* locked : {"one/s2.dcm", "locked", "outer/inner"})
    fs::permissions(dir / locked, fs::perms::owner_all);  // for TempDir's removal
}

TEST(DicomMessages, ASubfolderThatCannotBeReadIsListedAsRefusedBesideASeries) {
  const std::optional<std::string> prefix = as_unprivileged_user();
  if (!prefix) GTEST_SKIP() << "running as root without setpriv: no user that permissions stop";
  TempDir dir;
  fs::permissions(dir.path(), fs::perms::all);
  write_series(dir / "series", 3);
  write_series(dir / "series" / "more", 2);
  fs::permissions(dir / "series" / "more", fs::perms::none);
  const test::CliResult r = test::run_cli("info " + (dir / "series").string(), *prefix);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("refused: " + (dir / "series" / "more").string() +
                          ": cannot read the folder: Permission denied"),
            std::string::npos)
      << r.output;
  fs::permissions(dir / "series" / "more", fs::perms::owner_all);
}

}  // namespace
}  // namespace imx
