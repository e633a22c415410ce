// Issue 48, item 1: every reader of the format registry opens its file through the one guarded
// open, so a FIFO, a device, a folder or a symbolic link loop is refused at once, by name, and
// never blocks the reader (a FIFO opened before any check used to hang `render` for ever).
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <future>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "intermix/error.hpp"
#include "io/mesh/mesh_formats.hpp"
#include "io/overlay/overlay_formats.hpp"
#include "io/streamlines/streamline_formats.hpp"
#include "io/volume/volume_formats.hpp"
#include "labels/label_table_formats.hpp"
#include "registration/transform_file.hpp"
#include "registration/transform_formats.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using namespace std::chrono_literals;

// How long a reader may take to refuse a file that is not one: far more than any refusal needs.
constexpr auto kFast = 10s;

enum class Bad { fifo, device, folder, loop };

const char* name_of(Bad bad) {
  switch (bad) {
    case Bad::fifo:
      return "fifo";
    case Bad::device:
      return "device";
    case Bad::folder:
      return "folder";
    case Bad::loop:
      return "loop";
  }
  return "";
}

// What the message must say the file is ("" where a format may itself be a folder).
std::string kind_said(Bad bad) {
  switch (bad) {
    case Bad::fifo:
      return "is a FIFO (named pipe)";
    case Bad::device:
      return "is a character device";
    case Bad::folder:
      return "";
    case Bad::loop:
      return "symbolic link loop";
  }
  return "";
}

// A FIFO, /dev/null behind a link, an empty folder or a link to itself, named `name` in `dir`.
std::filesystem::path make_bad(const std::filesystem::path& dir, Bad bad, const std::string& ext) {
  const std::filesystem::path p = dir / (std::string(name_of(bad)) + ext);
  switch (bad) {
    case Bad::fifo:
      EXPECT_EQ(::mkfifo(p.c_str(), 0600), 0) << p;
      break;
    case Bad::device:
      std::filesystem::create_symlink("/dev/null", p);
      break;
    case Bad::folder:
      std::filesystem::create_directory(p);
      break;
    case Bad::loop:
      std::filesystem::create_symlink(p.filename(), p);
      break;
  }
  return p;
}

// Runs `read` on another thread: "" when it threw an error naming `file` (and saying `kind`)
// within kFast, else what went wrong. A reader blocked in a FIFO's open is released by opening
// the FIFO's other end, so that a failing test ends.
std::string refused_fast(const std::filesystem::path& file, const std::string& kind,
                         const std::function<void()>& read) {
  std::packaged_task<std::string()> task([&] {
    try {
      read();
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  });
  std::future<std::string> result = task.get_future();
  std::thread reader(std::move(task));
  const bool hung = result.wait_for(kFast) != std::future_status::ready;
  while (result.wait_for(50ms) != std::future_status::ready) {
    const int fd = ::open(file.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd >= 0) ::close(fd);
  }
  reader.join();
  const std::string message = result.get();
  if (hung) return "hung (blocked for more than 10 s), then: " + message;
  if (message == "(no error)") return "accepted it";
  if (message.find(file.string()) == std::string::npos)
    return "an error that does not name the file: " + message;
  if (!kind.empty() && message.find(kind) == std::string::npos)
    return fmt::format("an error that does not say '{}': {}", kind, message);
  return "";
}

struct Reader {
  std::string row;  // "volume NRRD" and the like
  std::string ext;  // the file name's extension
  std::function<void(const std::filesystem::path&)> read;
};

std::string first_ext(const detail::FormatInfo& info) {
  return info.extensions.empty() ? ".bin" : std::string(info.extensions.front());
}

// Every reader function of every row of the format registry, given the row's first extension.
std::vector<Reader> every_reader() {
  std::vector<Reader> out;
  const auto label = [](const detail::FormatInfo& info, const char* part) {
    return fmt::format("{} {} ({})", detail::file_kind_name(info.kind), info.name, part);
  };
  for (const detail::VolumeFormat& f : detail::volume_formats_table()) {
    if (f.whole)
      out.push_back({label(f.info, "whole"), first_ext(f.info),
                     [&f](const std::filesystem::path& p) { f.whole(p, 0); }});
    if (f.header)
      out.push_back({label(f.info, "header"), first_ext(f.info),
                     [&f](const std::filesystem::path& p) { f.header(p); }});
    if (f.region)
      out.push_back(
          {label(f.info, "region"), first_ext(f.info), [&f](const std::filesystem::path& p) {
             f.region(p, VoxelBox{glm::ivec3(0), glm::ivec3(1)}, 0);
           }});
  }
  for (const detail::MeshFormat& f : detail::mesh_formats_table())
    if (f.read)
      out.push_back({label(f.info, "read"), first_ext(f.info),
                     [&f](const std::filesystem::path& p) { f.read(p); }});
  for (const detail::OverlayFormat& f : detail::overlay_formats_table())
    if (f.read)
      out.push_back({label(f.info, "read"), first_ext(f.info),
                     [&f](const std::filesystem::path& p) { f.read(p, -1); }});
  for (const detail::TransformFileFormat& f : detail::transform_formats_table())
    out.push_back({label(f.info, "read"), first_ext(f.info),
                   [](const std::filesystem::path& p) { read_transform_file(p); }});
  for (const labels_detail::LabelTableFormat& f : labels_detail::label_table_formats_table())
    if (f.read)
      out.push_back({label(f.info, "read"), first_ext(f.info),
                     [&f](const std::filesystem::path& p) { f.read(p, 0); }});
  for (const detail::StreamlineFormat& f : detail::streamline_formats_table()) {
    if (f.read)
      out.push_back(
          {label(f.info, "read"), first_ext(f.info), [&f](const std::filesystem::path& p) {
             std::vector<std::string> n;
             f.read(p, n);
           }});
    if (f.read_values)
      out.push_back(
          {label(f.info, "values"), first_ext(f.info), [&f](const std::filesystem::path& p) {
             std::vector<std::string> n;
             Streamlines tracks;
             f.read_values(p, tracks, n, p.parent_path() / "tracks.tck");
           }});
  }
  for (const detail::ConnectomeFormat& f : detail::connectome_formats_table())
    if (f.read)
      out.push_back(
          {label(f.info, "read"), first_ext(f.info), [&f](const std::filesystem::path& p) {
             std::vector<std::string> n;
             f.read(p, n);
           }});
  return out;
}

TEST(InputGuard, EveryRegistryReaderRefusesAFifoDeviceFolderAndLinkLoopFast) {
  const std::vector<Reader> readers = every_reader();
  ASSERT_GT(readers.size(), 40u);
  size_t cases = 0;
  for (const Reader& r : readers) {
    for (Bad bad : {Bad::fifo, Bad::device, Bad::folder, Bad::loop}) {
      test::TempDir dir;
      const std::filesystem::path file = make_bad(dir.path(), bad, r.ext);
      const std::string fault = refused_fast(file, kind_said(bad), [&] { r.read(file); });
      EXPECT_EQ(fault, "") << r.row << ", given " << name_of(bad) << r.ext;
      ++cases;
    }
  }
  EXPECT_EQ(cases, readers.size() * 4);
  RecordProperty("cases", static_cast<int>(cases));
}

// The read_* entry points that choose by name and content, and the files a file names.
TEST(InputGuard, FilesNamedByOtherFilesAreGuardedToo) {
  test::TempDir dir;
  // An FSL matrix's moving image (FLIRT's -in), read for its header.
  test::write_bytes(dir / "m.mat", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  const std::filesystem::path moving = make_bad(dir.path(), Bad::fifo, ".nii.gz");
  EXPECT_EQ(refused_fast(moving, "is a FIFO",
                         [&] {
                           read_transform_file(dir / "m.mat", {moving, moving});
                         }),
            "");
}

// `intermix render` given a FIFO, alone or as a surface's overlay: GIfTI's were opened to be told
// apart (surface or data) before any check, and blocked for ever.
TEST(InputGuard, RenderOfAFifoFailsFastNamingIt) {
  test::TempDir dir;
  const std::filesystem::path out = dir / "x.png", surface = dir / "tri.obj";
  test::write_bytes(surface, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  for (const char* name : {"fifo.nii.gz", "fifo.gii", "fifo.curv", "fifo.func.gii"}) {
    const std::filesystem::path fifo = dir / name;
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const bool overlay = std::string(name) != "fifo.nii.gz" && std::string(name) != "fifo.gii";
    const std::string args = fmt::format("render {}{} -o {}", overlay ? surface.string() + " " : "",
                                         fifo.string(), out.string());
    std::string output;
    const std::string fault = refused_fast(fifo, "", [&] {
      const test::CliResult r = test::run_cli(args);
      output = r.output;
      throw std::runtime_error(r.exit_code == 0 ? "(no error)" : r.output);
    });
    EXPECT_EQ(fault, "") << args;
    EXPECT_NE(output.find(fifo.string() + ": is a FIFO (named pipe), not a regular file"),
              std::string::npos)
        << args << "\n"
        << output;
    EXPECT_FALSE(std::filesystem::exists(out)) << args;
  }
}

}  // namespace
}  // namespace imx
