// Tests for the scene's "csg" block, mesh interiors and the CSG and mixing render keys (CSG.md
// §5 P1, P2).
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/colour.hpp"
#include "intermix/io.hpp"
#include "intermix/scene.hpp"
#include "io/mesh/mesh_topology.hpp"
#include "scene_fixture.hpp"
#include "shared_data.hpp"
#include "temp_dir.hpp"

namespace imx {
namespace {

using test::error_of;
using test::parse;
using test::parse_error;

using test::mesh_json;
using test::volume_json;

// skin, bone (volumes), ball, brick (meshes), sheet (an open quad), axial (a plane).
std::string objects() {
  return test::shapes_objects("skin", "bone");
}

std::string scene_with(const std::string& csg, const std::string& rest = "",
                       const std::string& object_list = objects()) {
  return test::with_objects(object_list, R"("csg": )" + csg + rest);
}

const CsgNode& node(const Scene& s, int index) {
  return s.csg->nodes.at(static_cast<size_t>(index));
}

// The leaf's object name, or "" for an operator.
std::string leaf_name(const Scene& s, int index) {
  const CsgNode& n = node(s, index);
  if (n.op != CsgOp::primitive) return "";
  return n.object.kind == ObjectKind::volume ? s.volumes.at(n.object.index).name
                                             : s.meshes.at(n.object.index).name;
}

// "(skin - ball) + bone" style text of a subtree, to compare shapes.
std::string shape(const Scene& s, int index) {
  const CsgNode& n = node(s, index);
  switch (n.op) {
    case CsgOp::primitive:
      return leaf_name(s, index);
    case CsgOp::union_of:
      return "(" + shape(s, n.a) + " + " + shape(s, n.b) + ")";
    case CsgOp::intersection:
      return "(" + shape(s, n.a) + " * " + shape(s, n.b) + ")";
    case CsgOp::difference:
      return "(" + shape(s, n.a) + " - " + shape(s, n.b) + ")";
  }
  return "?";
}

std::string shape(const Scene& s) {
  return shape(s, s.csg->root);
}

// ---- P1: valid expressions ----------------------------------------------------------------

TEST(CsgScene, BinaryForm) {
  Scene s = parse(scene_with(R"({"op": "union",
      "a": {"op": "difference", "a": "skin", "b": "ball"}, "b": "bone"})"));
  ASSERT_TRUE(s.csg);
  EXPECT_EQ(shape(s), "((skin - ball) + bone)");
  EXPECT_EQ(s.csg->nodes.size(), 5u);
  const CsgNode& root = node(s, s.csg->root);
  EXPECT_EQ(root.op, CsgOp::union_of);
  const CsgNode& skin = node(s, node(s, root.a).a);
  EXPECT_EQ(skin.op, CsgOp::primitive);
  EXPECT_EQ(skin.object.kind, ObjectKind::volume);
  EXPECT_EQ(skin.object.index, 0);
  EXPECT_EQ(skin.presence, CsgPresence::opacity);  // a volume's default
  const CsgNode& ball = node(s, node(s, root.a).b);
  EXPECT_EQ(ball.object.kind, ObjectKind::mesh);
  EXPECT_EQ(ball.object.index, 0);
  EXPECT_EQ(ball.presence, CsgPresence::region);  // a mesh's only presence
  // The leaves name the same objects as scene order: skin is objects[0], ball objects[2].
  EXPECT_EQ(s.order[2].kind, ball.object.kind);
  EXPECT_EQ(s.order[2].index, ball.object.index);
  EXPECT_EQ(s.render.method, "csg");  // the default for a scene with a csg block
}

TEST(CsgScene, OfListsFoldLeftDeep) {
  EXPECT_EQ(shape(parse(scene_with(R"({"op": "union", "of": ["skin", "bone", "ball"]})"))),
            "((skin + bone) + ball)");
  EXPECT_EQ(shape(parse(
                scene_with(R"({"op": "intersection", "of": ["skin", "bone", "ball", "brick"]})"))),
            "(((skin * bone) * ball) * brick)");
  // The first minus each of the rest.
  EXPECT_EQ(shape(parse(scene_with(R"({"op": "difference", "of": ["skin", "ball", "brick"]})"))),
            "((skin - ball) - brick)");
  EXPECT_EQ(
      shape(parse(scene_with(
          R"({"op": "difference", "of": ["skin", {"op": "union", "of": ["ball", "brick"]}]})"))),
      "(skin - (ball + brick))");
}

TEST(CsgScene, ExplicitLeavesAndRepeats) {
  Scene s = parse(scene_with(R"({"op": "intersection",
      "a": {"object": "skin", "presence": "region"},
      "b": {"op": "union", "of": [{"object": "ball", "presence": "region"}, {"object": "bone"},
                                  {"object": "skin", "presence": "region"}]}})"));
  EXPECT_EQ(shape(s), "(skin * ((ball + bone) + skin))");
  const CsgNode& root = node(s, s.csg->root);
  EXPECT_EQ(node(s, root.a).presence, CsgPresence::region);
  EXPECT_EQ(node(s, node(s, node(s, root.b).a).b).presence, CsgPresence::opacity);  // bone
  // The same object twice is the same primitive: x - x is legal (and empty).
  EXPECT_EQ(shape(parse(scene_with(R"({"op": "difference", "a": "ball", "b": "ball"})"))),
            "(ball - ball)");
}

TEST(CsgScene, OnePrimitiveIsAnExpression) {
  Scene s = parse(scene_with(R"("brick")"));
  ASSERT_TRUE(s.csg);
  ASSERT_EQ(s.csg->nodes.size(), 1u);
  EXPECT_EQ(s.csg->root, 0);
  EXPECT_EQ(leaf_name(s, 0), "brick");
}

TEST(CsgScene, NullMeansNoCsg) {
  Scene s = parse(scene_with("null"));
  EXPECT_FALSE(s.csg);
  EXPECT_EQ(s.render.method, "auto");
  EXPECT_FALSE(parse(R"({"objects": []})").csg);
}

TEST(CsgScene, ExplicitMethodWins) {
  Scene s = parse(scene_with(R"("ball")", R"(, "render": {"method": "reference"})"));
  EXPECT_EQ(s.render.method, "reference");
  // A render block without a method still gets csg.
  EXPECT_EQ(parse(scene_with(R"("ball")", R"(, "render": {"spp": 4})")).render.method, "csg");
}

TEST(CsgScene, Overrides) {
  const std::string text =
      scene_with(R"({"op": "union", "a": {"op": "difference", "a": "skin", "b": "brick"},
                     "b": "bone"})");
  Scene plain = parse(text, {"csg=null"});
  EXPECT_FALSE(plain.csg);
  EXPECT_EQ(plain.render.method, "auto");
  EXPECT_EQ(shape(parse(text, {"csg.a.b=ball"})), "((skin - ball) + bone)");
  EXPECT_EQ(shape(parse(text, {R"(csg.a.b={"object": "ball", "presence": "region"})"})),
            "((skin - ball) + bone)");
  EXPECT_EQ(shape(parse(text, {"csg.b=brick", "csg.op=intersection"})), "((skin - brick) * brick)");

  const std::string list = scene_with(R"({"op": "difference", "of": ["skin", "ball", "bone"]})");
  EXPECT_EQ(shape(parse(list, {"csg.of.2=brick"})), "((skin - ball) - brick)");
  EXPECT_EQ(shape(parse(list, {"csg.of[1]=bone", "csg.of.2=brick"})), "((skin - bone) - brick)");
  // Overrides reach the validation like the file's own text.
  EXPECT_CONTAINS(parse_error(list, {"csg.of.2=axial"}),
                  "scene.json: csg.of[2]: 'axial' is a plane");
  EXPECT_CONTAINS(error_of([&] { parse(list, {"csg.of.3=brick"}); }),
                  "csg.of has 3 elements, there is no element 3");
  // A scene without csg gains one.
  EXPECT_EQ(
      shape(parse(scene_with("null"), {"csg={\"op\": \"union\", \"of\": [\"ball\", \"brick\"]}"})),
      "(ball + brick)");
}

TEST(CsgScene, MeshInterior) {
  Scene s = parse(scene_with(
      R"({"op": "difference", "a": "brick", "b": "ball"})", "",
      mesh_json("ball", R"("primitive": "sphere", "radius": 10)",
                R"("interior": {"color": [1, 0.5, 0], "opacity": 0.25, "unit_distance": 2})") +
          ", " + mesh_json("brick", R"("primitive": "box", "size": 20)", R"("interior": {})")));
  ASSERT_TRUE(s.meshes[0].interior);
  EXPECT_EQ(s.meshes[0].interior->color, glm::vec3(1, srgb_decode(0.5f), 0));  // display, decoded
  EXPECT_EQ(s.meshes[0].interior->opacity, 0.25f);
  EXPECT_EQ(s.meshes[0].interior->unit_distance, 2.0);
  ASSERT_TRUE(s.meshes[1].interior);  // defaults
  EXPECT_EQ(s.meshes[1].interior->color, glm::vec3(1.0f));
  EXPECT_EQ(s.meshes[1].interior->opacity, 0.0f);
  EXPECT_EQ(s.meshes[1].interior->unit_distance, 1.0);
  EXPECT_FALSE(parse(scene_with(R"("ball")")).meshes[0].interior);
}

using test::cube_ply;

TEST(CsgScene, InwardMeshIsFlippedOnlyWhereItIsAPrimitive) {
  test::TempDir dir;
  dir.write("inward.ply", cube_ply(true));
  ASSERT_LT(check_closed(read_mesh(dir.path() / "inward.ply")).signed_volume, 0.0);
  const std::string list = mesh_json("cutter", R"("file": "inward.ply")") + ", " +
                           mesh_json("copy", R"("file": "inward.ply")") + ", " + mesh_json("ball");
  Scene s = parse(scene_with(R"({"op": "difference", "a": "ball", "b": "cutter"})", "", list), {},
                  dir.path());
  MeshTopology cutter = check_closed(*s.meshes[0].mesh);
  EXPECT_TRUE(cutter.closed());
  EXPECT_NEAR(cutter.signed_volume, 1.0, 1e-9);
  // The other object from the same file is not a primitive and keeps its winding.
  EXPECT_NEAR(check_closed(*s.meshes[1].mesh).signed_volume, -1.0, 1e-9);
  EXPECT_GT(check_closed(*s.meshes[2].mesh).signed_volume, 0.0);
}

TEST(CsgScene, MirroredMeshStaysOutward) {
  // transform_mesh already rewinds a mirrored mesh, so the parser has nothing to flip.
  Scene s =
      parse(scene_with(R"("ball")", "",
                       mesh_json("ball", R"("primitive": "cylinder", "radius": 10, "height": 30)",
                                 R"("transform": {"scale": [-1, 1, 2]})")));
  MeshTopology t = check_closed(*s.meshes[0].mesh);
  EXPECT_TRUE(t.closed());
  EXPECT_GT(t.signed_volume, 0.0);
}

TEST(CsgScene, RenderSettings) {
  Scene s = parse(R"({"objects": [)" + volume_json("ct") + ", " + volume_json("pet") + ", " +
                  volume_json("mr") +
                  R"(], "render": {"csg_simplify": "full", "csg_presence_threshold": 0.05,
                     "csg_max_states": 100, "mixing": "exclusive",
                     "mixing_priority": ["pet", ["ct", "mr"]], "mixing_threshold": 0.5}})");
  EXPECT_EQ(s.render.csg_simplify, "full");
  EXPECT_EQ(s.render.csg_presence_threshold, 0.05);
  EXPECT_EQ(s.render.csg_max_states, 100);
  EXPECT_EQ(s.render.mixing, "exclusive");
  ASSERT_EQ(s.render.mixing_priority.size(), 2u);
  EXPECT_EQ(s.render.mixing_priority[0], std::vector<std::string>{"pet"});
  EXPECT_EQ(s.render.mixing_priority[1], (std::vector<std::string>{"ct", "mr"}));
  EXPECT_EQ(s.render.mixing_threshold, 0.5);

  RenderSettings defaults = parse(R"({"objects": []})").render;
  EXPECT_EQ(defaults.csg_simplify, "merge");
  EXPECT_EQ(defaults.csg_presence_threshold, 0.0);
  EXPECT_EQ(defaults.csg_max_states, 4096);
  EXPECT_EQ(defaults.mixing, "inclusive");
  EXPECT_TRUE(defaults.mixing_priority.empty());
  EXPECT_EQ(defaults.mixing_threshold, 0.0);
  EXPECT_EQ(parse(R"({"objects": [], "render": {"csg_simplify": "none"}})").render.csg_simplify,
            "none");
  EXPECT_EQ(
      parse(R"({"objects": [], "render": {"csg_max_states": 1000000}})").render.csg_max_states,
      1000000);
}

// ---- P2: errors ---------------------------------------------------------------------------

TEST(CsgSceneErrors, UnknownNames) {
  EXPECT_CONTAINS(parse_error(scene_with(R"({"op": "union", "a": "skin", "b": "bal"})")),
                  "scene.json: csg.b: no object named 'bal' (did you mean 'ball'?)");
  EXPECT_CONTAINS(parse_error(scene_with(R"({"op": "union", "a": {"object": "skn"}, "b": "x"})")),
                  "scene.json: csg.a.object: no object named 'skn' (did you mean 'skin'?)");
  std::string msg = parse_error(scene_with(R"({"op": "union", "of": ["skin", "zzz"]})"));
  EXPECT_CONTAINS(msg, "scene.json: csg.of[1]: no object named 'zzz'");
  EXPECT_EQ(msg.find("did you mean"), std::string::npos) << msg;
}

TEST(CsgSceneErrors, WrongKindsOfObject) {
  EXPECT_CONTAINS(parse_error(scene_with(R"({"op": "difference", "a": "skin", "b": "axial"})")),
                  "scene.json: csg.b: 'axial' is a plane; CSG primitives are volumes and closed "
                  "meshes");
  for (const char* style : {"iso", "mip", "xray"}) {
    std::string list = volume_json("ct", fmt::format(R"("style": "{}", "iso_value": 50)", style)) +
                       ", " + mesh_json("ball");
    EXPECT_CONTAINS(parse_error(scene_with(R"({"op": "union", "a": "ball", "b": "ct"})", "", list)),
                    fmt::format("scene.json: csg.b: 'ct' is a volume of style {}; CSG primitives "
                                "are dvr volumes and closed meshes",
                                style));
  }
}

TEST(CsgSceneErrors, OpenMeshes) {
  EXPECT_CONTAINS(parse_error(scene_with(R"({"op": "difference", "a": "skin", "b": "sheet"})")),
                  "scene.json: csg.b: mesh 'sheet' is not closed: 4 open edges");
  // An open mesh outside the expression is fine.
  EXPECT_NO_THROW(parse(scene_with(R"({"op": "difference", "a": "skin", "b": "ball"})")));

  test::TempDir dir;
  dir.write("twisted.ply", cube_ply(false, true));
  EXPECT_CONTAINS(
      parse_error(scene_with(R"("twisted")", "", mesh_json("twisted", R"("file": "twisted.ply")")),
                  {}, dir.path()),
      "scene.json: csg: mesh 'twisted' is not consistently wound: 6 directed edges "
      "without its reverse");

  SKIP_WITHOUT_SHARED_DATA("bunny.ply");
  const std::filesystem::path bunny = test::shared_data("bunny.ply");
  const std::string list = mesh_json("bunny", fmt::format(R"("file": "{}")", bunny.string()));
  std::string msg = parse_error(scene_with(R"({"object": "bunny"})", "", list));
  EXPECT_CONTAINS(msg, "scene.json: csg: mesh 'bunny' is not closed: ");
  EXPECT_CONTAINS(msg, " open edges");
}

TEST(CsgSceneErrors, Structure) {
  EXPECT_CONTAINS(parse_error(scene_with(
                      R"({"op": "union", "a": "skin", "b": "ball", "of": ["bone", "ball"]})")),
                  "scene.json: csg: give either \"a\" and \"b\" or \"of\", not both");
  EXPECT_CONTAINS(parse_error(scene_with(R"({"op": "union", "of": ["skin"]})")),
                  "scene.json: csg.of: needs at least 2 operands, got 1");
  EXPECT_CONTAINS(parse_error(scene_with(R"({"op": "union", "of": "skin"})")),
                  "scene.json: csg.of: expected a list of operands, got string \"skin\"");
  EXPECT_CONTAINS(parse_error(scene_with(R"({"op": "union"})")),
                  "scene.json: csg: needs operands: \"a\" and \"b\", or \"of\"");
  EXPECT_CONTAINS(parse_error(scene_with(R"({"op": "union", "a": "skin"})")),
                  "scene.json: csg: missing required key 'b'");
  EXPECT_CONTAINS(parse_error(scene_with(R"({"a": "skin", "b": "ball"})")),
                  "scene.json: csg: missing required key 'op'");
  EXPECT_CONTAINS(parse_error(scene_with(R"({"op": "unoin", "a": "skin", "b": "ball"})")),
                  "scene.json: csg.op: \"unoin\" is not one of union, intersection, difference "
                  "(did you mean 'union'?)");
  EXPECT_CONTAINS(
      parse_error(scene_with(R"({"op": "union", "a": {"op": "difference", "opp": 1}, "b": "x"})")),
      "scene.json: csg.a.opp: unknown key (did you mean 'op'?)");
  EXPECT_CONTAINS(parse_error(scene_with(R"({"object": "ball", "op": "union"})")),
                  "scene.json: csg: a node is either a primitive {\"object\": ...} or an operator");
  EXPECT_CONTAINS(
      parse_error(scene_with(R"({"op": "union", "of": ["ball", "skin"], "presence": "region"})")),
      "scene.json: csg.presence: only a primitive {\"object\": name, \"presence\": ...} has a "
      "presence");
  EXPECT_CONTAINS(parse_error(scene_with(R"({"op": "union", "of": ["ball", 3]})")),
                  "scene.json: csg.of[1]: expected an object name, {\"object\": name, "
                  "\"presence\": ...} or {\"op\": ...}, got number 3");
  EXPECT_CONTAINS(parse_error(scene_with(R"({"op": "union", "of": ["ball", null]})")),
                  "scene.json: csg.of[1]: expected an object name");
  EXPECT_CONTAINS(parse_error(scene_with("[]")), "scene.json: csg: expected an object name");
  EXPECT_CONTAINS(parse_error(scene_with("\"ball\"", R"(, "csgg": 1)")),
                  "scene.json: csgg: unknown key (did you mean 'csg'?)");
}

TEST(CsgSceneErrors, Presence) {
  EXPECT_CONTAINS(parse_error(scene_with(R"({"object": "skin", "presence": "regio"})")),
                  "scene.json: csg.presence: \"regio\" is not one of opacity, region (did you "
                  "mean 'region'?)");
  EXPECT_CONTAINS(parse_error(scene_with(R"({"object": "ball", "presence": "opacity"})")),
                  "scene.json: csg.presence: mesh 'ball' can only have presence \"region\"");
  EXPECT_CONTAINS(
      parse_error(scene_with(
          R"({"op": "union", "a": "skin", "b": {"object": "skin", "presence": "region"}})")),
      "scene.json: csg.b.presence: 'skin' has presence opacity at csg.a; an object has one "
      "presence in the expression");
  EXPECT_CONTAINS(
      parse_error(scene_with(
          R"({"op": "union", "of": [{"object": "skin", "presence": "region"}, "bone", "skin"]})")),
      "scene.json: csg.of[2]: 'skin' has presence region at csg.of[0]");
}

// A scene of `n` objects made by `make(name)` and their union.
std::string union_of_many(int n, const std::function<std::string(const std::string&)>& make) {
  std::string list, names;
  for (int i = 0; i < n; ++i) {
    std::string name = fmt::format("p{}", i);
    list += (i ? ", " : "") + make(name);
    names += fmt::format("{}\"{}\"", i ? ", " : "", name);
  }
  return scene_with(R"({"op": "union", "of": [)" + names + "]}", "", list);
}

TEST(CsgSceneErrors, AtMost64Primitives) {
  auto box = [](const std::string& name) {
    return mesh_json(name, R"("primitive": "box", "size": 1)");
  };
  Scene s = parse(union_of_many(64, box));
  EXPECT_EQ(s.csg->nodes.size(), 64u + 63u);
  EXPECT_CONTAINS(parse_error(union_of_many(65, box)),
                  "scene.json: csg.of[64]: at most 64 primitives; 'p64' is the 65th");
  // Repeats do not count: 65 leaves, 64 primitives.
  std::string list, names;
  for (int i = 0; i < 64; ++i) list += (i ? ", " : "") + box(fmt::format("p{}", i));
  for (int i = 0; i < 65; ++i) names += fmt::format("{}\"p{}\"", i ? ", " : "", i % 64);
  EXPECT_NO_THROW(parse(scene_with(R"({"op": "union", "of": [)" + names + "]}", "", list)));
}

TEST(CsgSceneErrors, AtMost16Volumes) {
  auto vol = [](const std::string& name) { return volume_json(name); };
  EXPECT_NO_THROW(parse(union_of_many(16, vol)));
  EXPECT_CONTAINS(parse_error(union_of_many(17, vol)),
                  "scene.json: csg.of[16]: at most 16 volumes (a ray holds 16); 'p16' is the "
                  "17th volume");
}

// `levels` operators nested through "a".
std::string nested(int levels) {
  // Built from both ends in linear time: wrapping the string once per level copied ~10 GB for
  // 20,000 levels, 1.6 s here and 82 s under ASan.
  std::string csg;
  for (int i = 0; i < levels; ++i) csg += R"({"op": "union", "a": )";
  csg += "\"skin\"";
  for (int i = 0; i < levels; ++i) csg += R"(, "b": "ball"})";
  return csg;
}

TEST(CsgSceneErrors, NestingDeeperThan256) {
  Scene s = parse(scene_with(nested(256)));
  EXPECT_EQ(s.csg->nodes.size(), 2u * 256 + 1);
  std::string path = "csg";
  for (int i = 0; i < 256; ++i) path += ".a";
  EXPECT_CONTAINS(parse_error(scene_with(nested(257))),
                  "scene.json: " + path + ": nesting deeper than 256 levels");
  // Far deeper does not overflow the stack: the check comes before the descent, and past 1024
  // JSON levels the parser itself stops first.
  EXPECT_CONTAINS(parse_error(scene_with(nested(500))), ": nesting deeper than 256 levels");
  EXPECT_CONTAINS(parse_error(scene_with(nested(20000))), ": JSON nested deeper than 1024");

  // An "of" list folds into one level per extra operand.
  auto list = [](int n) {
    std::string names;
    for (int i = 0; i < n; ++i) names += i ? ", \"ball\"" : "\"skin\"";
    return scene_with(R"({"op": "intersection", "of": [)" + names + "]}");
  };
  EXPECT_NO_THROW(parse(list(257)));
  EXPECT_CONTAINS(parse_error(list(258)),
                  "scene.json: csg.of[257]: nesting deeper than 256 levels (an \"of\" list of n "
                  "operands nests n - 1 levels)");
}

TEST(CsgSceneErrors, InteriorOnlyOnPrimitives) {
  const std::string list =
      volume_json("skin") + ", " + mesh_json("ball") + ", " +
      mesh_json("brick", R"("primitive": "box", "size": 20)", R"("interior": {"opacity": 0.5})");
  EXPECT_CONTAINS(parse_error(scene_with(R"({"op": "union", "a": "skin", "b": "ball"})", "", list)),
                  "scene.json: objects[2].interior: only CSG primitives have an interior (mesh "
                  "'brick' is not in the csg expression)");
  EXPECT_NO_THROW(parse(scene_with(R"({"op": "union", "a": "skin", "b": "brick"})", "", list)));
  // "csg": null is the file without CSG (`--set csg=null`): its interiors are kept, unused.
  EXPECT_NO_THROW(parse(scene_with("null", "", list)));
  EXPECT_CONTAINS(parse_error(R"({"objects": [)" + list + "]}"),
                  "scene.json: objects[2].interior: only CSG primitives have an interior");
}

TEST(CsgSceneErrors, InteriorValues) {
  auto error = [](const std::string& interior) {
    return parse_error(scene_with(
        R"("ball")", "", mesh_json("ball", R"("primitive": "sphere", "radius": 5)", interior)));
  };
  EXPECT_CONTAINS(error(R"("interior": {"opacity": 2})"),
                  "scene.json: objects[0].interior.opacity: 2 is not in [0, 1]");
  EXPECT_CONTAINS(error(R"("interior": {"unit_distance": 0})"),
                  "scene.json: objects[0].interior.unit_distance: 0 is not in [1e-06, 1000000]");
  EXPECT_CONTAINS(error(R"("interior": {"colour": [1, 0, 0]})"),
                  "scene.json: objects[0].interior.colour: unknown key (did you mean 'color'?)");
  EXPECT_CONTAINS(error(R"("interior": {"color": [2, 0, 0]})"),
                  "scene.json: objects[0].interior.color[0]: 2 is not in [0, 1]");
  EXPECT_CONTAINS(error(R"("interior": 1)"),
                  "scene.json: objects[0].interior: expected an object, got number 1");
  EXPECT_CONTAINS(error(R"("interiour": {})"),
                  "scene.json: objects[0].interiour: unknown key (did you mean 'interior'?)");
}

std::string render_error(const std::string& render) {
  return parse_error(R"({"objects": [)" + volume_json("ct") + ", " + volume_json("pet") + ", " +
                     mesh_json("ball") + R"(], "render": )" + render + "}");
}

TEST(CsgSceneErrors, RenderSettings) {
  EXPECT_CONTAINS(render_error(R"({"csg_simplify": "merged"})"),
                  "scene.json: render.csg_simplify: \"merged\" is not one of none, merge, full "
                  "(did you mean 'merge'?)");
  EXPECT_CONTAINS(render_error(R"({"mixing": "exclusiv"})"),
                  "scene.json: render.mixing: \"exclusiv\" is not one of inclusive, exclusive "
                  "(did you mean 'exclusive'?)");
  EXPECT_CONTAINS(render_error(R"({"csg_presence_threshold": 1.5})"),
                  "scene.json: render.csg_presence_threshold: 1.5 is not in [0, 1]");
  EXPECT_CONTAINS(render_error(R"({"csg_max_states": 0})"),
                  "scene.json: render.csg_max_states: 0 is not in [1, 1000000]");
  EXPECT_CONTAINS(render_error(R"({"csg_max_states": 1000001})"),
                  "scene.json: render.csg_max_states: 1000001 is not in [1, 1000000]");
  EXPECT_CONTAINS(render_error(R"({"csg_max_states": 2.5})"),
                  "scene.json: render.csg_max_states: expected an integer");
  EXPECT_CONTAINS(render_error(R"({"mixing_threshold": -0.1})"),
                  "scene.json: render.mixing_threshold: -0.1 is not in [0, 1]");
  EXPECT_CONTAINS(render_error(R"({"mixing_sthreshold": 0})"),
                  "scene.json: render.mixing_sthreshold: unknown key (did you mean "
                  "'mixing_threshold'?)");
}

TEST(CsgSceneErrors, MixingPriority) {
  EXPECT_CONTAINS(render_error(R"({"mixing_priority": ["ct", "pte"]})"),
                  "scene.json: render.mixing_priority[1]: no volume named 'pte' (did you mean "
                  "'pet'?)");
  EXPECT_CONTAINS(render_error(R"({"mixing_priority": [["ct", "ball"]]})"),
                  "scene.json: render.mixing_priority[0][1]: 'ball' is a mesh, not a volume");
  EXPECT_CONTAINS(render_error(R"({"mixing_priority": ["ct", ["pet", "ct"]]})"),
                  "scene.json: render.mixing_priority[1][1]: 'ct' is already at "
                  "render.mixing_priority[0] (a volume has one priority)");
  EXPECT_CONTAINS(render_error(R"({"mixing_priority": ["ct", []]})"),
                  "scene.json: render.mixing_priority[1]: an empty group");
  EXPECT_CONTAINS(render_error(R"({"mixing_priority": ["ct", 2]})"),
                  "scene.json: render.mixing_priority[1]: expected a volume name or a list of "
                  "names, got number 2");
  EXPECT_CONTAINS(render_error(R"({"mixing_priority": [["ct", 2]]})"),
                  "scene.json: render.mixing_priority[0][1]: expected a string, got number 2");
  EXPECT_CONTAINS(render_error(R"({"mixing_priority": "ct"})"),
                  "scene.json: render.mixing_priority: expected a list of volume names or of "
                  "lists of names, got string \"ct\"");
}

}  // namespace
}  // namespace imx
