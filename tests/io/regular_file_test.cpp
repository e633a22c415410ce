// Non-regular files are refused where a regular file is read or written: a FIFO would block a
// reader forever, and renaming over a device or FIFO would replace it (issue 17).
#include "io/streams/regular_file.hpp"

#include <sys/stat.h>

#include <fstream>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "io/streams/atomic_file.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::expect_error;
using test::TempDir;

std::filesystem::path fifo(const TempDir& dir, const std::string& name) {
  const std::filesystem::path p = dir / name;
  EXPECT_EQ(::mkfifo(p.c_str(), 0600), 0);
  return p;
}

TEST(RegularFile, EveryReaderRefusesAFifoWithoutOpeningIt) {
  TempDir dir;
  for (const char* name : {"v.nrrd", "v.nii.gz", "v.mha"})
    expect_error([&] { read_volume(fifo(dir, name)); }, {name, "is a FIFO (named pipe)"});
  expect_error([&] { read_mesh(fifo(dir, "m.obj")); }, {"m.obj", "is a FIFO"});
  expect_error([&] { read_mesh(fifo(dir, "m.ply")); }, {"m.ply", "is a FIFO"});
  expect_error([&] { read_png(fifo(dir, "i.png")); }, {"i.png", "is a FIFO"});
}

TEST(RegularFile, ADetachedDataFileMustBeRegularToo) {
  TempDir dir;
  fifo(dir, "data.raw");
  std::ofstream(dir / "h.nhdr") << "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\n"
                                   "encoding: raw\ndata file: data.raw\n";
  expect_error([&] { read_volume(dir / "h.nhdr"); },
               {"data.raw (data file of", "h.nhdr", "is a FIFO"});
  std::ofstream(dir / "h.mhd") << "ObjectType = Image\nNDims = 3\nDimSize = 2 2 2\n"
                                  "ElementType = MET_UCHAR\nElementDataFile = data.raw\n";
  expect_error([&] { read_volume(dir / "h.mhd"); }, {"data.raw (data file of", "is a FIFO"});
}

TEST(RegularFile, OutputOntoAFifoIsRefusedAndTheFifoKept) {
  TempDir dir;
  const std::filesystem::path out = fifo(dir, "out.png");
  expect_error([&] { write_file_atomically(out, [](std::ostream& o) { o << "x"; }); },
               {"out.png", "is a FIFO", "only regular files are written"});
  EXPECT_TRUE(std::filesystem::is_fifo(out));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.png"});  // no temporary left
}

TEST(RegularFile, LinksAreFollowedAndLoopsNamed) {
  TempDir dir;
  std::ofstream(dir / "real.txt") << "x";
  std::filesystem::create_symlink(dir / "real.txt", dir / "link.txt");
  EXPECT_NO_THROW(require_regular_file(dir / "link.txt"));
  std::filesystem::create_symlink(dir / "b", dir / "a");
  std::filesystem::create_symlink(dir / "a", dir / "b");
  expect_error([&] { require_regular_file(dir / "a"); }, {"a", "symbolic link loop"});
  expect_error([&] { require_regular_file(dir / "none"); }, {"none", "no such file"});
  expect_error([&] { require_regular_file(dir.path()); }, {"is a directory"});
  expect_error([&] { require_regular_file("/dev/null"); }, {"/dev/null", "character device"});
  EXPECT_NO_THROW(require_regular_or_new_file(dir / "new.png"));
  expect_error([&] { require_regular_or_new_file("/dev/null"); },
               {"/dev/null", "character device", "only regular files are written"});
}

}  // namespace
}  // namespace imx
