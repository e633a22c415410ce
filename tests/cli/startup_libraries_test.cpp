// The libraries only some inputs need are plugins opened on first use
// (src/io/registry/plugin_loader.hpp): assimp (with draco and minizip) for OBJ, STL, OFF and glTF
// meshes, libhdf5 for MINC-2, Open MPI for --distributed, FFmpeg for movies. Start-up, a NIfTI or
// DICOM conversion and a volume render map none of them (the dynamic loader's own report,
// LD_DEBUG=files, says what was mapped); a mesh of an assimp format maps the mesh plugin and reads
// as before, a MINC-2 file the MINC plugin, a distributed render the MPI plugin, a movie the movie
// plugin; a plugin that cannot be loaded is one error naming the paths tried (and the mesh file).
// The DICOM test uses ../shared/data/dicom/ts (skipped without it), the MINC test h5py
// (/usr/bin/python3) to write its file.
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

namespace fs = std::filesystem;
using test::contains;
using test::run_cli;
using test::TempDir;

// The loader's report names the C library (so it is there), and none of the plugin libraries.
void expect_no_plugin_libraries(const test::CliResult& r) {
  ASSERT_TRUE(contains(r.output, "libc.so.6")) << r.output.substr(0, 2000);
  for (const char* library :
       {"libassimp", "libdraco", "libminizip", "libimx_mesh_assimp", "libmpi", "libopen-rte",
        "libopen-pal", "libhwloc", "libevent", "libimx_mpi", "libhdf5", "libimx_minc_hdf5",
        "libavcodec", "libavformat", "libswscale", "libx264", "libimx_movie_ffmpeg"})
    EXPECT_FALSE(contains(r.output, library)) << library;
}

// A unit square in the z = 0 plane as two triangles: an OBJ face that assimp triangulates.
void write_square_obj(const fs::path& file) {
  std::ofstream(file) << "v 0 0 0\nv 10 0 0\nv 10 10 0\nv 0 10 0\nf 1 2 3 4\n";
}

// A binary STL of one triangle.
void write_triangle_stl(const fs::path& file) {
  std::ofstream out(file, std::ios::binary);
  out << std::string(80, ' ');
  const uint32_t count = 1;
  out.write(reinterpret_cast<const char*>(&count), 4);
  const float values[12] = {0, 0, 1, 0, 0, 0, 20, 0, 0, 0, 30, 0};
  out.write(reinterpret_cast<const char*>(values), sizeof values);
  out.write("\0\0", 2);
}

TEST(StartUpLibraries, HelpMapsNeitherAssimpNorMpi) {
  expect_no_plugin_libraries(run_cli("--help", "LD_DEBUG=files "));
}

TEST(StartUpLibraries, NiftiConvertAndVolumeRenderMapNeitherAssimpNorMpi) {
  TempDir dir;
  ASSERT_EQ(
      run_cli(fmt::format("phantom sphere --size 16 -o {}", (dir / "s.nii").string())).exit_code,
      0);
  const test::CliResult convert =
      run_cli(fmt::format("convert {} -o {}", (dir / "s.nii").string(), (dir / "s.nrrd").string()),
              "LD_DEBUG=files ");
  ASSERT_EQ(convert.exit_code, 0) << convert.output;
  ASSERT_TRUE(fs::exists(dir / "s.nrrd"));
  expect_no_plugin_libraries(convert);
  const test::CliResult render =
      run_cli(fmt::format("render {} --width 16 --height 16 -o {}", (dir / "s.nii").string(),
                          (dir / "s.png").string()),
              "LD_DEBUG=files ");
  ASSERT_EQ(render.exit_code, 0) << render.output;
  ASSERT_TRUE(fs::exists(dir / "s.png"));
  expect_no_plugin_libraries(render);
}

TEST(StartUpLibraries, DicomConvertMapsNeitherAssimpNorMpi) {
  SKIP_WITHOUT_SHARED_DATA("dicom/ts");
  TempDir dir;
  const test::CliResult r =
      run_cli(fmt::format("convert {} -o {}", (test::shared_data("dicom/ts") / "1.dcm").string(),
                          (dir / "1.nii").string()),
              "LD_DEBUG=files ");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_no_plugin_libraries(r);
}

TEST(StartUpLibraries, ObjAndStlMeshesLoadTheMeshPlugin) {
  TempDir dir;
  write_square_obj(dir / "square.obj");
  write_triangle_stl(dir / "triangle.stl");
  // The counts and bounds follow from the files written above.
  const std::pair<const char*, std::vector<std::string>> cases[] = {
      {"square.obj",
       {"triangles        2", "vertices         4", "[[0.0,0.0,0.0],[10.0,10.0,0.0]]"}},
      {"triangle.stl",
       {"triangles        1", "vertices         3", "[[0.0,0.0,0.0],[20.0,30.0,0.0]]"}}};
  for (const auto& [name, expected] : cases) {
    SCOPED_TRACE(name);
    const test::CliResult r =
        run_cli(fmt::format("info {}", (dir / name).string()), "LD_DEBUG=files ");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "libimx_mesh_assimp.so"));
    EXPECT_TRUE(contains(r.output, "libassimp"));
    for (const std::string& line : expected) EXPECT_TRUE(contains(r.output, line)) << r.output;
  }
}

TEST(StartUpLibraries, AMeshPluginThatCannotBeLoadedIsOneErrorNamingTheFileAndThePath) {
  TempDir dir;
  write_square_obj(dir / "square.obj");
  const fs::path missing = dir / "missing" / "libimx_mesh_assimp.so";
  const fs::path not_a_library = dir / "square.obj";
  for (const fs::path& plugin : {missing, not_a_library}) {
    SCOPED_TRACE(plugin.string());
    const test::CliResult r = run_cli(fmt::format("info {}", (dir / "square.obj").string()),
                                      fmt::format("IMX_MESH_PLUGIN={} ", plugin.string()));
    EXPECT_NE(r.exit_code, 0) << r.output;
    // One line names the mesh file, the plugin and the path tried; the path appears once more
    // only as the file named first when the plugin is the mesh itself.
    size_t lines = 0;
    for (size_t at = 0; (at = r.output.find("mesh plugin", at)) != std::string::npos; ++at) {
      const size_t begin = r.output.rfind('\n', at) + 1;
      const std::string line = r.output.substr(begin, r.output.find('\n', at) - begin);
      EXPECT_TRUE(contains(line, (dir / "square.obj").string() + ":")) << line;
      EXPECT_TRUE(contains(line, "tried: " + plugin.string() + " (")) << line;
      ++lines;
      at = r.output.find('\n', at);
      if (at == std::string::npos) break;
    }
    EXPECT_EQ(lines, 1u) << r.output;
  }
}

// A MINC-2 file of 4 x 3 x 2 zeros (zspace, yspace, xspace; uint8, identity scaling), written with
// h5py (/usr/bin/python3); whether the script succeeded.
bool write_minc2(const TempDir& dir, const fs::path& file) {
  std::ofstream(dir / "make_minc.py")
      << "import sys\nimport numpy as np, h5py\n"
         "with h5py.File(sys.argv[1], 'w') as f:\n"
         "    for d in ('xspace', 'yspace', 'zspace'):\n"
         "        v = f.create_dataset('minc-2.0/dimensions/' + d, data=np.int32(0))\n"
         "        v.attrs['spacing'] = np.bytes_('regular__')\n"
         "    zeros = np.zeros((4, 3, 2), np.uint8)\n"
         "    image = f.create_dataset('minc-2.0/image/0/image', data=zeros)\n"
         "    image.attrs['dimorder'] = np.bytes_('zspace,yspace,xspace')\n"
         "    f['minc-2.0/image/0/image-min'] = 0.0\n"
         "    f['minc-2.0/image/0/image-max'] = 255.0\n";
  return test::run_shell(fmt::format("/usr/bin/python3 {} {} 2>&1", (dir / "make_minc.py").string(),
                                     file.string()))
             .exit_code == 0;
}

// libhdf5 is not safe on hostile files: the MINC plugin runs in a child process
// (io/volume/minc_isolated.cpp), whose loader report is captured there, so this process maps none
// of it and still gives the file's dims.
TEST(StartUpLibraries, AMinc2FileIsReadWithLibhdf5OnlyInAChildProcess) {
  TempDir dir;
  if (test::run_shell("/usr/bin/python3 -c 'import h5py' 2>&1").exit_code != 0)
    GTEST_SKIP() << "/usr/bin/python3 has no h5py";
  ASSERT_TRUE(write_minc2(dir, dir / "zeros.mnc"));
  const test::CliResult r =
      run_cli(fmt::format("info {}", (dir / "zeros.mnc").string()), "LD_DEBUG=files ");
  ASSERT_EQ(r.exit_code, 0) << r.output.substr(r.output.size() > 4000 ? r.output.size() - 4000 : 0);
  EXPECT_FALSE(contains(r.output, "libimx_minc_hdf5.so"));
  EXPECT_FALSE(contains(r.output, "libhdf5"));
  EXPECT_TRUE(contains(r.output, "[4,3,2]")) << r.output;  // the file's dims, slowest first
}

// A scene of one small phantom volume, written by the program itself.
fs::path write_sphere_scene(const TempDir& dir) {
  const fs::path volume = dir / "s.nii", scene = dir / "s.json";
  EXPECT_EQ(run_cli(fmt::format("phantom sphere --size 16 -o {}", volume.string())).exit_code, 0);
  const test::CliResult r =
      run_cli(fmt::format("render {} --save-scene {} --width 16 --height 16 -o {}", volume.string(),
                          scene.string(), (dir / "s.png").string()));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return scene;
}

TEST(StartUpLibraries, AMovieLoadsTheMoviePlugin) {
  TempDir dir;
  ASSERT_EQ(
      run_cli(fmt::format("phantom sphere --size 16 -o {}", (dir / "s.nii").string())).exit_code,
      0);
  const test::CliResult r = run_cli(fmt::format("render {} --orbit 2 --width 16 --height 16 -o {}",
                                                (dir / "s.nii").string(), (dir / "s.mp4").string()),
                                    "LD_DEBUG=files ");
  ASSERT_EQ(r.exit_code, 0) << r.output.substr(r.output.size() > 4000 ? r.output.size() - 4000 : 0);
  EXPECT_TRUE(fs::exists(dir / "s.mp4"));
  EXPECT_TRUE(contains(r.output, "libimx_movie_ffmpeg.so"));
  EXPECT_TRUE(contains(r.output, "libavcodec.so"));
}

TEST(StartUpLibraries, DistributedRenderLoadsTheMpiPlugin) {
  TempDir dir;
  const fs::path scene = write_sphere_scene(dir);
  // One process without mpirun is a job of one rank. Leak checking is off under ASan, as in
  // tests/dist/mpi_render_test.py: Open MPI keeps registries until exit in plugins it unloads
  // first, so the reports name no module a suppression could match.
  const test::CliResult r =
      run_cli(fmt::format("render {} --distributed --width 16 --height 16 -o {}", scene.string(),
                          (dir / "d.png").string()),
              "ASAN_OPTIONS=\"${ASAN_OPTIONS}:detect_leaks=0\" LD_DEBUG=files ");
  if (contains(r.output, "built without MPI")) GTEST_SKIP() << "built without MPI";
  ASSERT_EQ(r.exit_code, 0) << r.output.substr(r.output.size() > 4000 ? r.output.size() - 4000 : 0);
  EXPECT_TRUE(fs::exists(dir / "d.png"));
  EXPECT_TRUE(contains(r.output, "libimx_mpi.so"));
  EXPECT_TRUE(contains(r.output, "libmpi.so"));
}

TEST(StartUpLibraries, AnMpiPluginThatCannotBeLoadedIsOneErrorNamingThePath) {
  TempDir dir;
  const fs::path scene = write_sphere_scene(dir);
  const fs::path missing = dir / "missing" / "libimx_mpi.so";
  const test::CliResult r =
      run_cli(fmt::format("render {} --distributed --width 16 --height 16 -o {}", scene.string(),
                          (dir / "d.png").string()),
              fmt::format("IMX_MPI_PLUGIN={} ", missing.string()));
  if (contains(r.output, "built without MPI")) GTEST_SKIP() << "built without MPI";
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(dir / "d.png"));
  size_t lines = 0;
  for (size_t at = 0; (at = r.output.find(missing.string(), at)) != std::string::npos;
       at += missing.string().size()) {
    const size_t begin = r.output.rfind('\n', at) + 1;
    const std::string line = r.output.substr(begin, r.output.find('\n', at) - begin);
    EXPECT_TRUE(contains(line, "--distributed needs the MPI plugin")) << line;
    EXPECT_TRUE(contains(line, "tried: " + missing.string() + " (")) << line;
    ++lines;
  }
  EXPECT_EQ(lines, 1u) << r.output;
}

}  // namespace
}  // namespace imx
