// `intermix render FILE... -o out.png`: a scene built from volume, DICOM and mesh files alone,
// with a camera that frames them, transfer functions by what each volume is, and the method
// auto picks; --save-scene writes a scene file that renders the same bytes.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "core/math.hpp"
#include "intermix/io.hpp"
#include "intermix/scene.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::run_cli;

// The share of the image's width or height (the larger) that the lit pixels span: the data on a
// black background.
double lit_extent(const Image& image) {
  int x0 = image.width(), x1 = -1, y0 = image.height(), y1 = -1;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const glm::vec4 p = image.at(x, y);
      if (std::max({p.r, p.g, p.b}) > 0.01f) {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
    }
  if (x1 < 0) return 0.0;
  return std::max(static_cast<double>(x1 - x0 + 1) / image.width(),
                  static_cast<double>(y1 - y0 + 1) / image.height());
}

TEST(CliFilesScene, AVolumeFileAloneRendersFramedWithAnAutomaticTransferFunction) {
  test::TempDir dir;
  const std::string volume = (dir.path() / "head.nii.gz").string();
  ASSERT_EQ(run_cli("phantom ct-head --size 64 -o " + volume).exit_code, 0);
  const std::string png = (dir.path() / "head.png").string();
  const std::string saved = (dir.path() / "head.json").string();
  // Not --quiet: the notes and the method's line are what the user reads.
  const test::CliResult r =
      test::run_shell(fmt::format("{} render {} -o {} --width 96 --height 80 --save-scene {} 2>&1",
                                  IMX_CLI_PATH, volume, png, saved));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("no transfer_function: CT"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("with mdvr (auto: volumes only)"), std::string::npos) << r.output;
  const double extent = lit_extent(read_png(png));
  EXPECT_GE(extent, 0.2);
  EXPECT_LE(extent, 0.9);
  // The saved scene has every choice written out and renders the same bytes.
  const std::string text = test::read_bytes(saved);
  EXPECT_NE(text.find("\"eye\""), std::string::npos);
  EXPECT_NE(text.find("\"preset\": \"ct-bone\""), std::string::npos);
  const std::string again = (dir.path() / "again.png").string();
  ASSERT_EQ(run_cli(fmt::format("render {} -o {}", saved, again)).exit_code, 0);
  EXPECT_EQ(test::read_bytes(again), test::read_bytes(png));
}

TEST(CliFilesScene, AViewTurnsTheCameraAndAMeshJoinsTheVolume) {
  test::TempDir dir;
  const std::string volume = (dir.path() / "head.nrrd").string();
  ASSERT_EQ(run_cli("phantom ct-head --size 48 -o " + volume).exit_code, 0);
  const std::string mesh = (dir.path() / "tri.obj").string();
  test::write_bytes(mesh, "v -200 0 0\nv 200 0 0\nv 0 0 200\nf 1 2 3\n");
  const std::string front = (dir.path() / "front.png").string();
  const std::string side = (dir.path() / "side.png").string();
  const test::CliResult a =
      run_cli(fmt::format("render {} {} -o {} --width 64 --height 64 "
                          "--view anterior",
                          volume, mesh, front));
  ASSERT_EQ(a.exit_code, 0) << a.output;
  const test::CliResult b = run_cli(
      fmt::format("render {} {} -o {} --width 64 --height 64 --view left", volume, mesh, side));
  ASSERT_EQ(b.exit_code, 0) << b.output;
  EXPECT_NE(test::read_bytes(front), test::read_bytes(side));
}

// `intermix serve FILE` serves the scene render would build, plus three hidden reading planes
// through the volume's centre; --save-scene writes that document as it starts.
TEST(CliFilesScene, ServeBuildsTheSameSceneWithHiddenReadingPlanes) {
  test::TempDir dir;
  const std::string volume = (dir.path() / "head.nrrd").string();
  ASSERT_EQ(run_cli("phantom ct-head --size 48 -o " + volume).exit_code, 0);
  const std::string saved = (dir.path() / "served.json").string();
  // The server runs until stopped: it has written the scene once it prints its address.
  const test::CliResult served = test::run_shell(
      fmt::format("cd {} && (timeout 60 {} serve {} --port 0 --save-scene {} & pid=$!; "
                  "for i in $(seq 600); do [ -s {} ] && break; sleep 0.1; done; kill $pid) 2>&1",
                  dir.path().string(), IMX_CLI_PATH, volume, saved, saved));
  const nlohmann::json doc = nlohmann::json::parse(test::read_bytes(saved));
  ASSERT_EQ(doc["objects"].size(), 4u) << served.output;
  const char* names[] = {"axial", "coronal", "sagittal"};
  for (int k = 0; k < 3; ++k) {
    const nlohmann::json& plane = doc["objects"][k + 1];
    EXPECT_EQ(plane["name"], names[k]);
    EXPECT_EQ(plane["visible"], false);
    EXPECT_EQ(plane["volume"], "head");
  }
  // The planes pass through the volume's centre; shown, the axial one is an MPR of it.
  const Scene scene = load_scene(saved);
  const VolumeData& v = *scene.volumes[0].data;
  const glm::dvec3 centre = transform_point(v.index_to_world, glm::dvec3(v.dims - 1) * 0.5);
  for (const PlaneObject& p : scene.planes) EXPECT_LT(glm::length(p.center - centre), 1e-3);
  const std::string png = (dir.path() / "axial.png").string();
  const test::CliResult shown =
      run_cli(fmt::format("render {} -o {} --width 48 --height 48 --set objects.axial.visible=true "
                          "--set objects.head.visible=false --view superior",
                          saved, png));
  ASSERT_EQ(shown.exit_code, 0) << shown.output;
  EXPECT_GT(lit_extent(read_png(png)), 0.3);
}

TEST(CliFilesScene, BadInputsGetOneClearError) {
  test::TempDir dir;
  const std::string text = (dir.path() / "notes.txt").string();
  test::write_bytes(text, "hello");
  test::CliResult r = run_cli(fmt::format("render {} -o {}/x.png", text, dir.path().string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find(text + ": '.txt' is not a format intermix reads; volumes:"),
            std::string::npos)
      << r.output;
  r = run_cli(
      fmt::format("render {}/missing.nii -o {}/x.png", dir.path().string(), dir.path().string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("missing.nii: no such file or folder"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "x.png"));
  r = run_cli(fmt::format("render {}/a.json -o {}/x.png --save-scene {}/s.json",
                          dir.path().string(), dir.path().string(), dir.path().string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--save-scene applies to a scene built from files"), std::string::npos)
      << r.output;
}

// Every real volume file and DICOM series of the shared data, with no scene file: an image the
// volume fills 20-90% of, rendered by the method auto picks, never the reference.
TEST(CliFilesScene, EveryRealVolumeRendersWithoutASceneFile) {
  SKIP_WITHOUT_SHARED_DATA("FLAIR.nii.gz");
  std::vector<std::filesystem::path> inputs;
  for (const char* file : {"FLAIR.nii.gz", "FLAIR.nrrd", "hippo.nii.gz", "mha.mha"})
    if (std::filesystem::exists(test::shared_data(file))) inputs.push_back(test::shared_data(file));
  for (const char* folder : {"dicom", "dicom4d"})
    if (std::filesystem::is_directory(test::shared_data(folder)))
      for (const auto& e : std::filesystem::directory_iterator(test::shared_data(folder)))
        if (e.is_directory() && e.path().filename() != "ref" && e.path().filename() != "ts")
          inputs.push_back(e.path());
  ASSERT_GE(inputs.size(), 4u);
  test::TempDir dir;
  for (const std::filesystem::path& input : inputs) {
    const std::string png = (dir.path() / (input.filename().string() + ".png")).string();
    const test::CliResult r = test::run_shell(fmt::format(
        "{} render {} -o {} --width 128 --height 128 2>&1", IMX_CLI_PATH, input.string(), png));
    ASSERT_EQ(r.exit_code, 0) << input << ": " << r.output;
    EXPECT_EQ(r.output.find("with reference"), std::string::npos) << r.output;
    const double extent = lit_extent(read_png(png));
    EXPECT_GE(extent, 0.2) << input;
    EXPECT_LE(extent, 0.9) << input;
  }
}

}  // namespace
}  // namespace imx
