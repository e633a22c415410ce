// Connectome objects end to end: node spheres where the nodes project, in their colour-map
// colours and sizes; edges as tubes of radius |weight| * edge_scale, hidden below edge_min;
// translucent beside a volume; `intermix render x.jcon` and `intermix render x.node x.edge`.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "presets/colormap.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

constexpr const char* kDense = "neuro/connectomes/connectome.jcon";
constexpr const char* kSparse = "neuro/connectomes/connectome2.jcon";
constexpr const char* kTemplate = "neuro/volumes/avg152T1_RL_nifti.nii.gz";

// An orthographic view from above (superior) onto z = 0, `mm` wide in `pixels`.
struct View {
  glm::dvec3 eye{0, 0, 500}, target{0, 0, 0}, up{0, -1, 0};
  double mm = 160.0;
  int pixels = 160;

  nlohmann::json json() const {
    return {{"eye", {eye.x, eye.y, eye.z}},
            {"target", {target.x, target.y, target.z}},
            {"up", {up.x, up.y, up.z}},
            {"projection", "orthographic"},
            {"ortho_height", mm}};
  }
  // Where world LPS point p lands in the image, in pixels (x right, y down).
  glm::dvec2 project(const glm::dvec3& p) const {
    const glm::dvec3 forward = glm::normalize(target - eye);
    const glm::dvec3 u = glm::normalize(up - glm::dot(up, forward) * forward);
    const glm::dvec3 right = glm::cross(forward, u);
    const double per_pixel = mm / pixels;
    return {0.5 * pixels + glm::dot(p - target, right) / per_pixel,
            0.5 * pixels - glm::dot(p - target, u) / per_pixel};
  }
  glm::vec4 at(const Image& image, const glm::dvec3& p) const {
    const glm::dvec2 px = project(p);
    return image.at(static_cast<int>(std::floor(px.x)), static_cast<int>(std::floor(px.y)));
  }
};

Image render_scene(const View& view, const nlohmann::json& objects, const char* method) {
  const nlohmann::json scene = {
      {"camera", view.json()},
      {"image", {{"width", view.pixels}, {"height", view.pixels}, {"background", {0, 0, 0, 0}}}},
      {"render", {{"method", method}, {"spp", 1}}},
      {"objects", objects}};
  return render(parse_scene(scene.dump(), ".", "test"));
}

// A node of a NiiVue connectome file as the test reads it (its JSON, RAS to LPS here).
struct Node {
  glm::dvec3 lps;
  double value = 0.0, size = 0.0;
};

struct NiivueFile {
  std::vector<Node> nodes;
  nlohmann::json json;
};

NiivueFile read_niivue(const std::filesystem::path& file) {
  NiivueFile f;
  f.json = nlohmann::json::parse(test::read_bytes(file.string()));
  const nlohmann::json& n = f.json["nodes"];
  if (n.is_object()) {  // the dense layout: arrays per field
    for (size_t i = 0; i < n["X"].size(); ++i)
      f.nodes.push_back({{-n["X"][i].get<double>(), -n["Y"][i].get<double>(), n["Z"][i]},
                         n["Color"][i],
                         n["Size"][i]});
  } else {
    for (const nlohmann::json& e : n)
      f.nodes.push_back({{-e["x"].get<double>(), -e["y"].get<double>(), e["z"]},
                         e["colorValue"],
                         e["sizeValue"]});
  }
  return f;
}

// The documented stand-ins for NiiVue's colour-map names (docs/streamlines.md).
Colormap niivue_map(const std::string& name) {
  if (name == "warm") return Colormap::red_yellow;
  if (name == "winter") return Colormap::blue_lightblue;
  return *find_colormap(name);
}

glm::vec3 node_colour(const NiivueFile& f, const Node& n) {
  const double lo = f.json["nodeMinColor"], hi = f.json["nodeMaxColor"];
  const std::string map = n.value < 0 ? f.json["nodeColormapNegative"] : f.json["nodeColormap"];
  return colormap_rgb(niivue_map(map), static_cast<float>((std::abs(n.value) - lo) / (hi - lo)));
}

// From the node's centre outward, away from the nodes' middle (where no edge runs), `d` mm.
glm::dvec3 outward(const std::vector<Node>& nodes, const Node& n, double d) {
  glm::dvec3 middle(0.0);
  for (const Node& m : nodes) middle += m.lps / static_cast<double>(nodes.size());
  glm::dvec3 away = n.lps - middle;
  away.z = 0.0;
  return n.lps + d * glm::normalize(away);
}

void expect_near(const glm::vec4& pixel, const glm::vec3& rgb, float tolerance,
                 const std::string& where) {
  EXPECT_GT(pixel.a, 0.99f) << where;
  EXPECT_NEAR(pixel.r, rgb.r, tolerance) << where;
  EXPECT_NEAR(pixel.g, rgb.g, tolerance) << where;
  EXPECT_NEAR(pixel.b, rgb.b, tolerance) << where;
}

// Each node of the real files: a sphere of radius size * nodeScale where it projects, in its
// colour; edges made thin so that none covers a node's centre from above.
TEST(Connectome, NodeSpheresLieWhereTheNodesProjectInTheirColours) {
  SKIP_WITHOUT_SHARED_DATA(kDense, kSparse);
  for (const char* name : {kDense, kSparse}) {
    const NiivueFile f = read_niivue(test::shared_data(name));
    ASSERT_EQ(f.nodes.size(), 4u);
    const View view;
    const Image image = render_scene(view,
                                     {{{"name", "net"},
                                       {"type", "connectome"},
                                       {"edge_scale", 0.25},
                                       {"shading", {{"enabled", false}}},
                                       {"source", {{"file", test::shared_data(name).string()}}}}},
                                     "zslab-hybrid");
    const double scale = f.json["nodeScale"];
    for (size_t i = 0; i < f.nodes.size(); ++i) {
      const Node& n = f.nodes[i];
      const double radius = n.size * scale;
      const std::string where = fmt::format("{} node {}", name, i);
      const glm::vec3 rgb = node_colour(f, n);
      expect_near(view.at(image, n.lps), rgb, 0.02f, where + " centre");
      expect_near(view.at(image, outward(f.nodes, n, 0.8 * radius)), rgb, 0.02f, where + " rim");
      EXPECT_LT(view.at(image, outward(f.nodes, n, 1.15 * radius)).a, 0.01f) << where;
    }
  }
}

// A BrainNet pair written here: four nodes on a rectangle (RAS), edges A-B 1, C-D 2, A-C 0.2,
// B-D 0.6.
struct BrainNet {
  std::filesystem::path node, edge;
  std::vector<glm::dvec3> lps = {{40, 20, 0}, {-40, 20, 0}, {40, -20, 0}, {-40, -20, 0}};
};

BrainNet write_brainnet(const test::TempDir& dir) {
  BrainNet b{dir / "net.node", dir / "net.edge"};
  std::ofstream node(b.node);
  node << "# x y z colour size name\n";
  const char* names[] = {"A", "B", "C", "D"};
  for (size_t i = 0; i < 4; ++i)
    node << fmt::format("{} {} {} 1 1 {}\n", -b.lps[i].x, -b.lps[i].y, b.lps[i].z, names[i]);
  std::ofstream edge(b.edge);
  edge << "0 1 0.2 0\n1 0 0 0.6\n0.2 0 0 2\n0 0.6 2 0\n";
  return b;
}

// The pixels along the image column through `p`, within `mm` of it, that something covers.
int covered_across(const View& view, const Image& image, const glm::dvec3& p, double mm) {
  int covered = 0;
  const glm::dvec2 centre = view.project(p);
  const int half = static_cast<int>(mm * view.pixels / view.mm);
  for (int dy = -half; dy <= half; ++dy)
    covered += image.at(static_cast<int>(centre.x), static_cast<int>(centre.y) + dy).a > 0.5f;
  return covered;
}

TEST(Connectome, EdgesShowAboveTheThresholdAsTubesOfTheirWeight) {
  test::TempDir dir;
  const BrainNet b = write_brainnet(dir);
  View view;
  view.mm = 100.0, view.pixels = 200;  // 0.5 mm a pixel
  const double edge_scale = 2.0, edge_min = 0.5, edge_max = 2.0;
  const Image image =
      render_scene(view,
                   {{{"name", "net"},
                     {"type", "connectome"},
                     {"node_scale", 3.0},
                     {"edge_scale", edge_scale},
                     {"edge_min", edge_min},
                     {"edge_max", edge_max},
                     {"shading", {{"enabled", false}}},
                     {"source", {{"file", b.node.string()}, {"edges", b.edge.string()}}}}},
                   "zslab-hybrid");
  const auto middle = [&](int i, int j) { return 0.5 * (b.lps[i] + b.lps[j]); };
  // A-C (0.2) is below edge_min: nothing; B-D (0.6) is above: drawn.
  EXPECT_LT(view.at(image, middle(0, 2)).a, 0.01f);
  EXPECT_GT(view.at(image, middle(1, 3)).a, 0.99f);
  // Widths across A-B (weight 1) and C-D (weight 2): 2 |w| edge_scale mm, the second twice the
  // first.
  const double per_mm = view.pixels / view.mm;
  const int thin = covered_across(view, image, middle(0, 1), 10.0);
  const int thick = covered_across(view, image, middle(2, 3), 10.0);
  EXPECT_NEAR(thin, 2 * 1.0 * edge_scale * per_mm, 1.5);
  EXPECT_NEAR(thick, 2 * 2.0 * edge_scale * per_mm, 1.5);
  EXPECT_NEAR(static_cast<double>(thick) / thin, 2.0, 0.25);
  // Colour: |w| through NiiVue's "warm" (intermix's red-yellow) from edge_min to edge_max.
  const auto edge_rgb = [&](double w) {
    return colormap_rgb(Colormap::red_yellow,
                        static_cast<float>((w - edge_min) / (edge_max - edge_min)));
  };
  expect_near(view.at(image, middle(0, 1)), edge_rgb(1.0), 0.02f, "A-B");
  expect_near(view.at(image, middle(2, 3)), edge_rgb(2.0), 0.02f, "C-D");
  // Nodes: value 1 of NiiVue's default range 0..4, radius 1 * 3 mm, over A-B's end (2 mm).
  expect_near(view.at(image, b.lps[0]), colormap_rgb(Colormap::red_yellow, 0.25f), 0.02f, "node A");
}

// A translucent connectome beside a volume (one that shows nothing), in zslab-hybrid and
// mdvr: each node's rim lets through 1 - opacity, the same in both.
TEST(Connectome, TranslucentBesideAVolumeInZslabHybridAndMdvr) {
  SKIP_WITHOUT_SHARED_DATA(kDense, kTemplate);
  const NiivueFile f = read_niivue(test::shared_data(kDense));
  const nlohmann::json volume = {
      {"name", "t1"},
      {"type", "volume"},
      {"source", {{"file", test::shared_data(kTemplate).string()}}},
      {"transfer_function", {{"points", {{1e5, 1, 1, 1, 0}, {1e6, 1, 1, 1, 0}}}}}};
  const nlohmann::json net = {{"name", "net"},
                              {"type", "connectome"},
                              {"edge_scale", 0.25},
                              {"opacity", 0.5},
                              {"shading", {{"enabled", false}}},
                              {"source", {{"file", test::shared_data(kDense).string()}}}};
  const View view;
  const Image hybrid = render_scene(view, nlohmann::json::array({volume, net}), "zslab-hybrid");
  const Image mdvr = render_scene(view, nlohmann::json::array({volume, net}), "mdvr");
  for (size_t i = 0; i < f.nodes.size(); ++i) {
    const Node& n = f.nodes[i];
    const glm::dvec3 rim = outward(f.nodes, n, 0.8 * n.size * f.json["nodeScale"].get<double>());
    const glm::vec4 a = view.at(hybrid, rim), b = view.at(mdvr, rim);
    EXPECT_NEAR(a.a, 0.5f, 0.02f) << "zslab-hybrid node " << i;
    EXPECT_NEAR(b.a, 0.5f, 0.02f) << "mdvr node " << i;
    const glm::vec3 rgb = node_colour(f, n) * 0.5f;  // premultiplied
    EXPECT_NEAR(glm::length(glm::vec3(a) - rgb), 0.0f, 0.03f) << "zslab-hybrid node " << i;
    EXPECT_NEAR(glm::length(glm::vec3(b) - rgb), 0.0f, 0.03f) << "mdvr node " << i;
  }
}

TEST(Connectome, RenderOfANodeAndEdgeMakesOneConnectomeObject) {
  test::TempDir dir;
  const BrainNet b = write_brainnet(dir);
  const std::string png = (dir / "net.png").string(), saved = (dir / "net.json").string();
  const test::CliResult r =
      test::run_cli(fmt::format("render {} {} -o {} --width 64 --height 64 --save-scene {}",
                                b.node.string(), b.edge.string(), png, saved));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json document = nlohmann::json::parse(test::read_bytes(saved));
  ASSERT_EQ(document["objects"].size(), 1u) << document.dump(2);
  const nlohmann::json& o = document["objects"][0];
  EXPECT_EQ(o["type"], "connectome");
  EXPECT_EQ(o["source"]["edges"], b.edge.string());
  const Image image = read_png(png);
  size_t drawn = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) drawn += image.at(x, y).r + image.at(x, y).g > 0.1f;
  EXPECT_GT(drawn, 20u);
  // An .edge alone says what it needs.
  const test::CliResult alone = test::run_cli(fmt::format("render {} -o {}", b.edge.string(), png));
  EXPECT_NE(alone.exit_code, 0);
  EXPECT_TRUE(test::contains(alone.output, ".node")) << alone.output;
}

TEST(Connectome, RenderOfAJconDrawsIt) {
  SKIP_WITHOUT_SHARED_DATA(kDense);
  test::TempDir dir;
  const std::string png = (dir / "net.png").string();
  const test::CliResult r = test::run_cli(fmt::format("render {} -o {} --width 64 --height 64",
                                                      test::shared_data(kDense).string(), png));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Image image = read_png(png);
  size_t drawn = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) drawn += image.at(x, y).a > 0.5f;
  EXPECT_GT(drawn, 50u);
}

TEST(Connectome, AnUnknownColourMapIsRefusedNamingTheField) {
  test::TempDir dir;
  const BrainNet b = write_brainnet(dir);
  const nlohmann::json net = {{"name", "net"},
                              {"type", "connectome"},
                              {"node_colormap", "batlow"},
                              {"source", {{"file", b.node.string()}}}};
  try {
    render_scene(View{}, nlohmann::json::array({net}), "zslab-hybrid");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_TRUE(test::contains(e.what(), "node_colormap")) << e.what();
    EXPECT_TRUE(test::contains(e.what(), "batlow")) << e.what();
  }
  // The same name in a NiiVue file: the error names the file's field.
  std::ofstream(dir / "bad.jcon")
      << R"({"nodeColormap": "batlow", "nodes": {"names": ["a"], "X": [0], "Y": [0], "Z": [0],
             "Color": [1], "Size": [1]}, "edges": [0]})";
  const nlohmann::json from_file = {
      {"name", "net"}, {"type", "connectome"}, {"source", {{"file", (dir / "bad.jcon").string()}}}};
  try {
    render_scene(View{}, nlohmann::json::array({from_file}), "zslab-hybrid");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_TRUE(test::contains(e.what(), "nodeColormap")) << e.what();
    EXPECT_TRUE(test::contains(e.what(), "bad.jcon")) << e.what();
  }
}

}  // namespace
}  // namespace imx
