// Connectome readers: NiiVue's JSON (.jcon) against Python's own json parse of the same file
// (NiiVue's rules written again in Python), BrainNet's .node/.edge against the arrays the test
// writes them from, the JSON sniff, and hostile files.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "intermix/error.hpp"
#include "intermix/streamlines.hpp"
#include "io/connectome/brainnet.hpp"
#include "io/connectome/jcon.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::read_bytes;
using test::TempDir;
using test::write_bytes;

bool have_python() {
  static const bool ok = std::system("/usr/bin/python3 -c 'import json' >/dev/null 2>&1") == 0;
  return ok;
}

// NiiVue's reading (nvconnectome.ts: convertLegacyConnectome, and the sparse layout as it is)
// in Python: one line per node (LPS), edge (upper triangle, or the pair turned round) and
// display field.
const char* kReferenceScript = R"PY(
import json, sys
d = json.load(open(sys.argv[1]))
out = open(sys.argv[2], 'w')
nodes = d['nodes']
if isinstance(nodes, dict):
    n = len(nodes['names'])
    rows = [(nodes['names'][i], nodes['X'][i], nodes['Y'][i], nodes['Z'][i],
             nodes['Color'][i], nodes['Size'][i]) for i in range(n)]
    edges = [(i, j, d['edges'][i * n + j]) for i in range(n) for j in range(i + 1, n)]
else:
    rows = [(v['name'], v['x'], v['y'], v['z'], v['colorValue'], v['sizeValue']) for v in nodes]
    edges = [(min(e['first'], e['second']), max(e['first'], e['second']), e['colorValue'])
             for e in d['edges']]
for name, x, y, z, c, s in rows:
    out.write('node\t%s\t%r\t%r\t%r\t%r\t%r\n' % (name, -float(x), -float(y), float(z), float(c), float(s)))
for a, b, w in edges:
    if w != 0:
        out.write('edge\t%d\t%d\t%r\n' % (a, b, float(w)))
for key in ['name', 'nodeColormap', 'nodeColormapNegative', 'nodeMinColor', 'nodeMaxColor',
            'nodeScale', 'edgeColormap', 'edgeColormapNegative', 'edgeMin', 'edgeMax', 'edgeScale']:
    if key in d:
        out.write('style\t%s\t%s\n' % (key, d[key]))
)PY";

struct Reference {
  std::vector<ConnectomeNode> nodes;
  std::vector<ConnectomeEdge> edges;
  std::vector<std::pair<std::string, std::string>> style;
};

Reference python_reference(const TempDir& dir, const std::filesystem::path& file) {
  write_bytes(dir / "ref.py", kReferenceScript);
  const std::string command = "/usr/bin/python3 '" + (dir / "ref.py").string() + "' '" +
                              file.string() + "' '" + (dir / "ref.txt").string() + "' 2>&1";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  Reference r;
  std::istringstream in(read_bytes(dir / "ref.txt"));
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> f;
    std::istringstream fields(line);
    for (std::string s; std::getline(fields, s, '\t');) f.push_back(s);
    if (f[0] == "node" && f.size() == 7) {
      ConnectomeNode n;
      n.name = f[1];
      n.position = {std::stof(f[2]), std::stof(f[3]), std::stof(f[4])};
      n.value = std::stof(f[5]);
      n.size = std::stof(f[6]);
      r.nodes.push_back(n);
    } else if (f[0] == "edge" && f.size() == 4) {
      r.edges.push_back({static_cast<uint32_t>(std::stoul(f[1])),
                         static_cast<uint32_t>(std::stoul(f[2])), std::stof(f[3])});
    } else if (f[0] == "style" && f.size() == 3) {
      r.style.emplace_back(f[1], f[2]);
    } else {
      ADD_FAILURE() << "reference line: " << line;
    }
  }
  return r;
}

std::string style_field(const ConnectomeStyle& s, const std::string& key) {
  const auto num = [](const std::optional<float>& v) {
    return v ? std::to_string(*v) : std::string("(absent)");
  };
  if (key == "name") return s.name.value_or("(absent)");
  if (key == "nodeColormap") return s.node_colormap.value_or("(absent)");
  if (key == "nodeColormapNegative") return s.node_colormap_negative.value_or("(absent)");
  if (key == "edgeColormap") return s.edge_colormap.value_or("(absent)");
  if (key == "edgeColormapNegative") return s.edge_colormap_negative.value_or("(absent)");
  if (key == "nodeMinColor") return num(s.node_min_color);
  if (key == "nodeMaxColor") return num(s.node_max_color);
  if (key == "nodeScale") return num(s.node_scale);
  if (key == "edgeMin") return num(s.edge_min);
  if (key == "edgeMax") return num(s.edge_max);
  if (key == "edgeScale") return num(s.edge_scale);
  return "(unknown key)";
}

void expect_same(const Connectome& got, const Reference& want) {
  ASSERT_EQ(got.nodes.size(), want.nodes.size());
  for (size_t i = 0; i < want.nodes.size(); ++i) {
    SCOPED_TRACE("node " + std::to_string(i));
    EXPECT_EQ(got.nodes[i].name, want.nodes[i].name);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(got.nodes[i].position[k], want.nodes[i].position[k], 1e-4);
    EXPECT_FLOAT_EQ(got.nodes[i].value, want.nodes[i].value);
    EXPECT_FLOAT_EQ(got.nodes[i].size, want.nodes[i].size);
  }
  ASSERT_EQ(got.edges.size(), want.edges.size());
  for (size_t i = 0; i < want.edges.size(); ++i) {
    SCOPED_TRACE("edge " + std::to_string(i));
    EXPECT_EQ(got.edges[i].a, want.edges[i].a);
    EXPECT_EQ(got.edges[i].b, want.edges[i].b);
    EXPECT_FLOAT_EQ(got.edges[i].weight, want.edges[i].weight);
  }
  for (const auto& [key, value] : want.style) {
    const std::string have = style_field(got.style, key);
    char* end = nullptr;
    const double number = std::strtod(value.c_str(), &end);
    if (end != value.c_str() && *end == '\0')
      EXPECT_FLOAT_EQ(std::stof(have), static_cast<float>(number)) << key;
    else
      EXPECT_EQ(have, value) << key;
  }
}

// The message of the imx::Error that `read` throws ("" and a failure when none is thrown).
template <class Read>
std::string error_of(Read read) {
  try {
    read();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no imx::Error";
  return {};
}

bool has_note(const std::vector<std::string>& notes, const std::string& part) {
  for (const std::string& n : notes)
    if (n.find(part) != std::string::npos) return true;
  return false;
}

// --- NiiVue's connectome JSON -------------------------------------------------------------

class SharedJcon : public ::testing::TestWithParam<const char*> {};

TEST_P(SharedJcon, MatchesPythonsParseWithNiivuesRules) {
  const std::string name = std::string("neuro/connectomes/") + GetParam();
  SKIP_WITHOUT_SHARED_DATA(name);
  if (!have_python()) GTEST_SKIP() << "/usr/bin/python3 is not available";
  TempDir dir;
  const std::filesystem::path file = test::shared_data(name);
  std::vector<std::string> notes;
  const Connectome c = detail::read_jcon(file, notes);
  const Reference want = python_reference(dir, file);
  ASSERT_FALSE(want.nodes.empty());
  EXPECT_FALSE(want.edges.empty());
  EXPECT_FALSE(want.style.empty());
  expect_same(c, want);
  EXPECT_TRUE(detail::looks_like_connectome_json(read_bytes(file)));
}

INSTANTIATE_TEST_SUITE_P(Connectome, SharedJcon,
                         ::testing::Values("connectome.jcon", "connectome2.jcon"));

TEST(ConnectomeJcon, DenseMatrixUsesTheUpperTriangleAsNiivueDoes) {
  SKIP_WITHOUT_SHARED_DATA("neuro/connectomes/connectome.jcon");
  std::vector<std::string> notes;
  detail::read_jcon(test::shared_data("neuro/connectomes/connectome.jcon"), notes);
  EXPECT_TRUE(has_note(notes, "not symmetric")) << ::testing::PrintToString(notes);
}

TEST(ConnectomeJcon, WrittenFilesAgreeWithPython) {
  if (!have_python()) GTEST_SKIP() << "/usr/bin/python3 is not available";
  TempDir dir;
  // Negative, fractional and exponent values; a symmetric matrix; names with blanks.
  write_bytes(dir / "dense.jcon", R"({"name": "three", "edgeMin": 0.5,
    "nodes": {"names": ["a b", "c", "d"], "X": [1.25, -2, 3e1], "Y": [0, -7.5, 8],
              "Z": [-1, 2, 3], "Color": [0.5, -1, 2], "Size": [1, 2.5, 3]},
    "edges": [0, -0.25, 3e-2,  -0.25, 0, 0,  3e-2, 0, 9]})");
  write_bytes(dir / "sparse.json", R"({"nodes": [
      {"name": "p", "x": -1, "y": 2, "z": 3.5, "colorValue": 1, "sizeValue": 2},
      {"name": "q", "x": 4, "y": -5, "z": 6, "colorValue": -2, "sizeValue": 0.5},
      {"name": "r", "x": 0, "y": 0, "z": 0, "colorValue": 0, "sizeValue": 1}],
    "edges": [{"first": 2, "second": 0, "colorValue": -4.5},
              {"first": 0, "second": 1, "colorValue": 0},
              {"first": 1, "second": 2, "colorValue": 7}]})");
  for (const char* name : {"dense.jcon", "sparse.json"}) {
    SCOPED_TRACE(name);
    std::vector<std::string> notes;
    const Connectome c = detail::read_jcon(dir / name, notes);
    expect_same(c, python_reference(dir, dir / name));
    EXPECT_TRUE(notes.empty()) << ::testing::PrintToString(notes);
    EXPECT_TRUE(detail::looks_like_connectome_json(read_bytes(dir / name)));
  }
}

TEST(ConnectomeJcon, SparseEdgesAreTurnedRoundAndRepeatsAndLoopsDropped) {
  TempDir dir;
  write_bytes(dir / "s.jcon", R"({"nodes": [{"x": 1, "y": 2, "z": 3}, {"x": 4, "y": 5, "z": 6}],
    "edges": [{"first": 1, "second": 0, "colorValue": 2}, {"first": 0, "second": 1,
    "colorValue": 3}, {"first": 1, "second": 1, "colorValue": 4}]})");
  std::vector<std::string> notes;
  const Connectome c = detail::read_jcon(dir / "s.jcon", notes);
  ASSERT_EQ(c.nodes.size(), 2u);
  EXPECT_EQ(c.nodes[1].position, glm::vec3(-4, -5, 6));
  EXPECT_EQ(c.nodes[0].size, 1.0f);
  ASSERT_EQ(c.edges.size(), 1u);
  EXPECT_EQ(c.edges[0].a, 0u);
  EXPECT_EQ(c.edges[0].b, 1u);
  EXPECT_EQ(c.edges[0].weight, 2.0f);
  EXPECT_TRUE(has_note(notes, "to itself"));
  EXPECT_TRUE(has_note(notes, "repeat"));
  EXPECT_TRUE(has_note(notes, "no name"));
  EXPECT_TRUE(has_note(notes, "no sizeValue"));
}

TEST(ConnectomeJcon, FreeSurferPointSetGivesNodes) {
  TempDir dir;
  write_bytes(dir / "points.json", R"({"data_type": "fs_pointset", "vox2ras": "scanner_ras",
    "points": [{"coordinates": {"x": 10.5, "y": -20, "z": 30}, "legacy_stat": 1,
                "comments": [{"text": "first"}, {"text": "more"}]},
               {"coordinates": {"x": -1, "y": 2, "z": -3}}]})");
  std::vector<std::string> notes;
  const Connectome c = detail::read_jcon(dir / "points.json", notes);
  ASSERT_EQ(c.nodes.size(), 2u);
  EXPECT_EQ(c.nodes[0].position, glm::vec3(-10.5f, 20, 30));
  EXPECT_EQ(c.nodes[1].position, glm::vec3(1, -2, -3));
  EXPECT_EQ(c.nodes[0].name, "first");
  EXPECT_EQ(c.nodes[1].name, "");
  EXPECT_TRUE(c.edges.empty());
  EXPECT_TRUE(has_note(notes, "point set")) << ::testing::PrintToString(notes);
  EXPECT_TRUE(detail::looks_like_connectome_json(read_bytes(dir / "points.json")));
}

TEST(ConnectomeJcon, HostileFilesGiveOneErrorNamingTheField) {
  TempDir dir;
  const std::string dense_nodes =
      R"("nodes": {"names": ["a", "b"], "X": [1, 2], "Y": [1, 2], "Z": [1, 2],
                   "Color": [1, 1], "Size": [1, 1]})";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{\"nodes\": ", "not valid JSON"},
      {"[1, 2]", "not a JSON object"},
      {R"({"edges": [1]})", "nodes is missing"},
      {R"({"nodes": 3, "edges": []})", "nodes is neither"},
      {R"({"nodes": {"names": [], "X": [], "Y": [], "Z": []}, "edges": []})", "at least one node"},
      {R"({"nodes": [], "edges": []})", "at least one node"},
      {R"({"nodes": {"names": ["a", "b"], "X": [1], "Y": [1, 2], "Z": [1, 2]}})",
       "nodes.X has 1 values, but nodes.names has 2"},
      {R"({"nodes": {"names": ["a"], "Y": [1], "Z": [1]}})", "nodes.X is missing"},
      {"{" + dense_nodes + R"(, "edges": [0, 1, 1])", "not valid JSON"},
      {"{" + dense_nodes + R"(, "edges": [0, 1, 1]})", "edges has 3 values, but 2 nodes need"},
      {"{" + dense_nodes + R"(, "edges": [0, "1", 1, 0]})", "edges[1] (row 0, column 1"},
      {"{" + dense_nodes + R"(, "edges": [0, 1e999, 1, 0]})", "1e999"},
      {"{" + dense_nodes + R"(, "edges": [0, 1e39, 1, 0]})", "not a finite number"},
      {"{" + dense_nodes + R"(, "edges": [[0, 1], [1, 0]]})", "edges has 2 values"},
      {"{" + dense_nodes + R"(, "edges": {"a": 1}})", "edges is an object"},
      {R"({"nodes": {"names": ["a"], "X": [null], "Y": [1], "Z": [1]}})", "nodes.X[0] is null"},
      {R"({"nodes": [{"x": 1, "y": 2}], "edges": []})", "nodes[0].z is missing"},
      {R"({"nodes": [{"x": 1, "y": 2, "z": 3}], "edges": [{"first": 0, "second": 1,
          "colorValue": 1}]})",
       "edges[0].second is 1, not the index of one of the 1 nodes"},
      {R"({"nodes": [{"x": 1, "y": 2, "z": 3}], "edges": [{"first": -1, "second": 0,
          "colorValue": 1}]})",
       "edges[0].first"},
      {R"({"nodes": [{"x": 1, "y": 2, "z": 3}, {"x": 1, "y": 2, "z": 3}],
          "edges": [{"first": 0, "second": 1}]})",
       "edges[0].colorValue is missing"},
      {R"({"nodes": [{"x": 1, "y": 2, "z": 3}], "edges": [1]})", "edges[0] is 1, not an edge"},
      {R"({"nodeScale": "big", "nodes": [{"x": 1, "y": 2, "z": 3}]})", "nodeScale is \"big\""},
      {R"({"data_type": "fs_pointset", "vox2ras": "tkreg", "points": []})", "vox2ras is \"tkreg\""},
      {R"({"data_type": "fs_pointset", "vox2ras": "scanner_ras", "points": []})",
       "points is empty"},
      {R"({"data_type": "fs_pointset", "points": [{"coordinates": {"x": 1, "y": 2}}]})",
       "points[0].coordinates.z is missing"},
      {std::string(10000, '[') + std::string(10000, ']'), "nested deeper"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::filesystem::path file = dir / ("bad" + std::to_string(i) + ".jcon");
    write_bytes(file, cases[i].first);
    std::vector<std::string> notes;
    const std::string message = error_of([&] { detail::read_jcon(file, notes); });
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find(cases[i].second), std::string::npos) << "case " << i << ": " << message;
  }
  std::vector<std::string> notes;
  EXPECT_THROW(detail::read_jcon(dir / "absent.jcon", notes), FileError);
  EXPECT_THROW(detail::read_jcon(dir.path(), notes), FileError);
}

// --- The JSON sniff ---------------------------------------------------------------------------

TEST(ConnectomeSniff, TellsConnectomesFromOtherJson) {
  using detail::looks_like_connectome_json;
  EXPECT_TRUE(looks_like_connectome_json(R"({"nodes": [], "edges": []})"));
  EXPECT_TRUE(looks_like_connectome_json("\xEF\xBB\xBF \n{\"edges\": 1, \"nodes\": 2}"));
  // A head cut before "edges": the node fields tell.
  EXPECT_TRUE(looks_like_connectome_json(R"({"nodes": {"names": ["a", "b"], "X": [1, )"));
  EXPECT_TRUE(looks_like_connectome_json(R"({"nodes": [{"name": "a", "colorValue": 1}, {"na)"));
  EXPECT_TRUE(looks_like_connectome_json(R"({"nodeColormap": "warm", "nodes": [)"));
  // Keys with "nodes" and "edges" below the top level, or node keys of other formats.
  EXPECT_FALSE(looks_like_connectome_json(R"({"graph": {"nodes": [], "edges": []}})"));
  EXPECT_FALSE(
      looks_like_connectome_json(R"({"asset": {"version": "2.0"}, "nodes": [{"mesh": 0}]})"));
  EXPECT_FALSE(looks_like_connectome_json(R"({"nodes": [{"id": 1}], "links": []})"));
  EXPECT_FALSE(looks_like_connectome_json(R"({"a": "\"nodes\": 1, \"edges\": 2"})"));
  EXPECT_FALSE(looks_like_connectome_json(R"([{"nodes": 1, "edges": 2}])"));
  EXPECT_TRUE(looks_like_connectome_json(R"({"data_type": "fs_pointset", "points": [)"));
  EXPECT_FALSE(looks_like_connectome_json(R"({"data_type": "other", "points": []})"));
  EXPECT_FALSE(looks_like_connectome_json(""));
  EXPECT_FALSE(looks_like_connectome_json("{"));
  EXPECT_FALSE(looks_like_connectome_json("}}}{"));
  EXPECT_FALSE(looks_like_connectome_json(std::string(100000, '{')));
}

TEST(ConnectomeSniff, SharedFilesAndTheirHeads) {
  SKIP_WITHOUT_SHARED_DATA("neuro/connectomes/connectome.jcon");
  const std::string bytes = read_bytes(test::shared_data("neuro/connectomes/connectome.jcon"));
  const size_t nodes = bytes.find("\"nodes\"");
  ASSERT_NE(nodes, std::string::npos);
  EXPECT_TRUE(detail::looks_like_connectome_json(std::string_view(bytes).substr(0, nodes + 10)));
  EXPECT_FALSE(detail::looks_like_connectome_json(std::string_view(bytes).substr(0, nodes)));
}

// --- BrainNet Viewer's .node and .edge -------------------------------------------------------

struct BrainNetFixture {
  std::vector<float> x, y, z, colour, size;
  std::vector<std::string> names;
  std::vector<float> matrix;  // n x n, symmetric
  size_t n() const { return x.size(); }
};

BrainNetFixture fixture() {
  BrainNetFixture f;
  const size_t n = 7;
  for (size_t i = 0; i < n; ++i) {
    f.x.push_back(-60.5f + 17.25f * i);
    f.y.push_back(30.0f - 11.125f * i);
    f.z.push_back(i % 2 ? -4.75f : 12.0f * i);
    f.colour.push_back(static_cast<float>(i % 3 + 1));
    f.size.push_back(0.5f * (i + 1));
    f.names.push_back(i == 3 ? "-" : "Region_" + std::to_string(i));
  }
  f.matrix.assign(n * n, 0.0f);
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n; ++b)
      if ((a + 2 * b) % 3 != 0)
        f.matrix[a * n + b] = f.matrix[b * n + a] = (a % 2 ? -1.0f : 1.0f) * (0.1f + 0.37f * b);
  return f;
}

// As BrainNet users write them: comments, blank lines, tabs, CRLF, commas in the matrix.
void write_fixture(const BrainNetFixture& f, const std::filesystem::path& node,
                   const std::filesystem::path& edge) {
  std::string text = "# x y z colour size name\n\n";
  char buf[256];
  for (size_t i = 0; i < f.n(); ++i) {
    std::snprintf(buf, sizeof buf, "%.9g\t%.9g %.9g  %.9g\t%.9g %s%s\n", f.x[i], f.y[i], f.z[i],
                  f.colour[i], f.size[i], f.names[i].c_str(), i == 2 ? "\r" : "");
    text += buf;
  }
  write_bytes(node, text);
  text = "% weights\n";
  for (size_t a = 0; a < f.n(); ++a) {
    for (size_t b = 0; b < f.n(); ++b) {
      std::snprintf(buf, sizeof buf, "%s%.9g", b == 0 ? "" : (a == 4 ? "," : " "),
                    f.matrix[a * f.n() + b]);
      text += buf;
    }
    text += a == 1 ? "\r\n\n" : "\n";
  }
  write_bytes(edge, text);
}

void expect_fixture(const Connectome& c, const BrainNetFixture& f) {
  ASSERT_EQ(c.nodes.size(), f.n());
  for (size_t i = 0; i < f.n(); ++i) {
    SCOPED_TRACE("node " + std::to_string(i));
    EXPECT_EQ(c.nodes[i].position, glm::vec3(-f.x[i], -f.y[i], f.z[i]));
    EXPECT_EQ(c.nodes[i].value, f.colour[i]);
    EXPECT_EQ(c.nodes[i].size, f.size[i]);
    EXPECT_EQ(c.nodes[i].name, f.names[i] == "-" ? "" : f.names[i]);
  }
  std::vector<ConnectomeEdge> want;
  for (uint32_t a = 0; a < f.n(); ++a)
    for (uint32_t b = a + 1; b < f.n(); ++b)
      if (f.matrix[a * f.n() + b] != 0.0f) want.push_back({a, b, f.matrix[a * f.n() + b]});
  ASSERT_EQ(c.edges.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(c.edges[i].a, want[i].a);
    EXPECT_EQ(c.edges[i].b, want[i].b);
    EXPECT_EQ(c.edges[i].weight, want[i].weight);
  }
}

TEST(ConnectomeBrainNet, ReadsNodesAndTheirMatrix) {
  TempDir dir;
  const BrainNetFixture f = fixture();
  write_fixture(f, dir / "net.node", dir / "weights.edge");
  std::vector<std::string> notes;
  expect_fixture(detail::read_brainnet(dir / "net.node", dir / "weights.edge", notes), f);
  EXPECT_TRUE(notes.empty()) << ::testing::PrintToString(notes);
}

TEST(ConnectomeBrainNet, FindsTheEdgeFileBesideItsNodes) {
  TempDir dir;
  const BrainNetFixture f = fixture();
  write_fixture(f, dir / "net.node", dir / "net.edge");
  std::vector<std::string> notes;
  expect_fixture(detail::read_brainnet(dir / "net.node", std::nullopt, notes), f);
  EXPECT_TRUE(has_note(notes, "net.edge")) << ::testing::PrintToString(notes);

  std::filesystem::remove(dir / "net.edge");
  notes.clear();
  const Connectome alone = detail::read_brainnet(dir / "net.node", std::nullopt, notes);
  EXPECT_EQ(alone.nodes.size(), f.n());
  EXPECT_TRUE(alone.edges.empty());
  EXPECT_TRUE(has_note(notes, "no edges")) << ::testing::PrintToString(notes);
}

TEST(ConnectomeBrainNet, TriangularMatrixGivesItsTriangle) {
  TempDir dir;
  BrainNetFixture f = fixture();
  write_fixture(f, dir / "net.node", dir / "unused.edge");
  for (bool keep_upper : {true, false}) {
    BrainNetFixture t = f;
    for (size_t a = 0; a < f.n(); ++a)
      for (size_t b = 0; b < a; ++b)
        (keep_upper ? t.matrix[a * f.n() + b] : t.matrix[b * f.n() + a]) = 0;
    write_fixture(t, dir / "net.node", dir / "tri.edge");
    std::vector<std::string> notes;
    expect_fixture(detail::read_brainnet(dir / "net.node", dir / "tri.edge", notes), f);
    EXPECT_TRUE(has_note(notes, keep_upper ? "lower triangle is zero" : "upper triangle is zero"))
        << ::testing::PrintToString(notes);
  }
}

TEST(ConnectomeBrainNet, HostileFilesGiveOneErrorNamingTheField) {
  TempDir dir;
  const std::string good_node = "1 2 3 1 1 a\n4 5 6 1 1 b\n";
  struct Case {
    std::string node, edge, expected;
  };
  const std::vector<Case> cases = {
      {"1 2 3 1 1\n", "", "line 1: 5 columns"},
      {"1 2 3 1 1 a\n# c\n4 5 6 1 1 b c\n", "", "line 3: more than 6 columns"},
      {"1 2 nan 1 1 a\n", "", "line 1: z is 'nan'"},
      {"1 2 3 1 inf a\n", "", "size is 'inf'"},
      {"1 2 3 1e39 1 a\n", "", "colour is '1e39'"},
      {"x 2 3 1 1 a\n", "", "x is 'x'"},
      {"# only a comment\n\n", "", "no nodes"},
      {"", "", "no nodes"},
      {good_node, "0 1\n1 0\n0 0\n", "more than 2 rows"},
      {good_node, "0 1 1\n1 0\n", "row 1 has more than 2 values"},
      {good_node, "0 1\n1    \n", "row 2 has 1 values"},
      {good_node, "0 1\n# one row\n", "1 rows, but there are 2 nodes"},
      {good_node, "0 x\n1 0\n", "row 1, column 2 is 'x'"},
      {good_node, "0 NaN\nNaN 0\n", "not a finite number"},
      {"1 2 3 1 1 a\n4 5 6 1 1 b\n7 8 9 1 1 c\n", "0 1 2\n1 0 3\n2 4 0\n",
       "not symmetric: row 3, column 2 is 4, but row 2, column 3 is 3"},
      {good_node, "0", "more than the file's 1 bytes"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::filesystem::path node = dir / ("bad" + std::to_string(i) + ".node");
    const std::filesystem::path edge = dir / ("bad" + std::to_string(i) + ".edge");
    write_bytes(node, cases[i].node);
    if (!cases[i].edge.empty()) write_bytes(edge, cases[i].edge);
    std::vector<std::string> notes;
    const std::string message = error_of([&] {
      detail::read_brainnet(node, cases[i].edge.empty() ? std::nullopt : std::optional(edge),
                            notes);
    });
    const std::filesystem::path& named = cases[i].edge.empty() ? node : edge;
    EXPECT_NE(message.find(named.string()), std::string::npos) << message;
    EXPECT_NE(message.find(cases[i].expected), std::string::npos)
        << "case " << i << ": " << message;
  }
}

TEST(ConnectomeBrainNet, EdgeMatrixTooBigForItsFileIsRefusedBeforeAllocating) {
  TempDir dir;
  std::string nodes;
  for (int i = 0; i < 100000; ++i) nodes += "1 2 3 1 1 -\n";
  write_bytes(dir / "big.node", nodes);
  write_bytes(dir / "big.edge", std::string(1000, '0'));
  std::vector<std::string> notes;
  const std::string message =
      error_of([&] { detail::read_brainnet(dir / "big.node", dir / "big.edge", notes); });
  EXPECT_NE(message.find("100000 x 100000"), std::string::npos) << message;
  EXPECT_THROW(detail::read_brainnet(dir / "absent.node", std::nullopt, notes), FileError);
}

}  // namespace
}  // namespace imx
