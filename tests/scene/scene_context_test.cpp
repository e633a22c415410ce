// A SceneContext kept between parses of edited documents (the Python package's Scene): sources
// read once and kept by identity, given in-memory sources, and imx::FileError for files that
// cannot be read.
#include <cerrno>

#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "intermix/io.hpp"
#include "phantoms/mesh_primitives.hpp"
#include "scene/overrides.hpp"
#include "scene/scene_parsers.hpp"
#include "temp_dir.hpp"

namespace imx::scene_json {
namespace {

using nlohmann::json;

json document() {
  return json::parse(R"({
    "objects": [
      {"name": "ct", "type": "volume", "source": {"phantom": "cube", "size": 16},
       "transfer_function": {"points": [[0, 0, 0, 0, 0], [255, 1, 1, 1, 1]]}},
      {"name": "ball", "type": "mesh", "source": {"primitive": "sphere", "radius": 5},
       "transform": {"translate": [1, 2, 3]}}
    ]
  })");
}

TEST(SceneContext, KeepsSourcesAndPlacedMeshesAcrossParses) {
  SceneContext context;
  json doc = document();
  const Scene first = parse_scene_document(doc, "doc", context);
  apply_override(doc, "objects.ct.transfer_function.points=[[0,0,0,0,0],[255,1,0,0,1]]", "doc");
  const Scene second = parse_scene_document(doc, "doc", context);
  EXPECT_EQ(first.volumes[0].data, second.volumes[0].data);
  EXPECT_EQ(first.meshes[0].mesh, second.meshes[0].mesh);
  EXPECT_NE(first.volumes[0].transfer_function.points[1].rgba.g,
            second.volumes[0].transfer_function.points[1].rgba.g);
  // A new transform places the mesh again; the loaded primitive is still the same.
  apply_override(doc, "objects.ball.transform.translate=[0,0,0]", "doc");
  const Scene third = parse_scene_document(doc, "doc", context);
  EXPECT_NE(second.meshes[0].mesh, third.meshes[0].mesh);
  EXPECT_EQ(third.meshes[0].mesh->positions.size(), second.meshes[0].mesh->positions.size());
  EXPECT_EQ(context.used.size(), 3u);  // the phantom, the primitive and its placement
}

TEST(SceneContext, AFreshParseReadsSourcesAgain) {
  const std::string text = document().dump();
  EXPECT_NE(parse_scene(text, {}, "a").volumes[0].data, parse_scene(text, {}, "b").volumes[0].data);
}

TEST(SceneContext, GivenVolumesAndMeshesByPlaceholder) {
  SceneContext context;
  auto volume = std::make_shared<const VolumeData>(make_phantom("cube", 16));
  auto mesh = std::make_shared<const Mesh>(make_box({4.0, 5.0, 6.0}));
  context.given_volumes["v1"] = volume;
  context.given_meshes["m1"] = mesh;
  json doc = document();
  doc["objects"][0]["source"] = {{"$volume", "v1"}};
  doc["objects"][1]["source"] = {{"$mesh", "m1"}};
  const Scene scene = parse_scene_document(doc, "scene dict", context);
  EXPECT_EQ(scene.volumes[0].data, volume);
  EXPECT_EQ(scene.meshes[0].mesh->positions.size(), mesh->positions.size());
  doc["objects"][0]["source"] = {{"$volume", "v2"}};
  EXPECT_EQ(test::error_of([&] { parse_scene_document(doc, "scene dict", context); }),
            "scene dict: objects[0].source.$volume: \"v2\" is not a volume of this scene");
}

TEST(SceneContext, GivenStreamlinesByPlaceholder) {
  SceneContext context;
  auto tracts = std::make_shared<Streamlines>();
  tracts->points = {{0, 0, 0}, {10, 0, 0}, {10, 5, 0}};
  tracts->offsets = {0, 3};
  context.given_streamlines["s1"] = tracts;
  context.given_meshes["m1"] = std::make_shared<const Mesh>(make_box({4.0, 5.0, 6.0}));
  json doc = {{"objects", json::array({{{"name", "t"},
                                        {"type", "streamlines"},
                                        {"source", {{"$streamlines", "s1"}}}}})}};
  const Scene scene = parse_scene_document(doc, "scene dict", context);
  EXPECT_EQ(scene.streamlines[0].streamlines, tracts);  // no transform: the given data itself
  doc["objects"][0]["source"] = {{"$streamlines", "s2"}};
  EXPECT_EQ(test::error_of([&] { parse_scene_document(doc, "scene dict", context); }),
            "scene dict: objects[0].source.$streamlines: \"s2\" is not a set of streamlines of "
            "this scene");
  doc["objects"][0]["source"] = {{"$mesh", "m1"}};
  EXPECT_EQ(test::error_of([&] { parse_scene_document(doc, "scene dict", context); }),
            "scene dict: objects[0].source: is a mesh the program gave, not streamlines");
}

TEST(SceneContext, FilesKnowNoPlaceholders) {
  json doc = document();
  doc["objects"][0]["source"] = {{"$volume", "v1"}};
  EXPECT_CONTAINS(test::error_of([&] { parse_scene(doc.dump(), {}, "s.json"); }),
                  "s.json: objects[0].source.$volume: unknown key");
}

TEST(SceneContext, FilesThatCannotBeReadAreFileErrors) {
  test::TempDir dir;
  json doc = document();
  doc["objects"][0]["source"] = {{"file", "missing.nrrd"}};
  try {
    parse_scene(doc.dump(), dir.path(), "s.json");
    FAIL() << "no error";
  } catch (const FileError& e) {
    EXPECT_EQ(e.code(), ENOENT);
    EXPECT_EQ(std::string(e.what()), "s.json: objects[0].source.file: no such file '" +
                                         (dir.path() / "missing.nrrd").string() + "'");
  }
  try {
    load_scene(dir.path());
    FAIL() << "no error";
  } catch (const FileError& e) {
    EXPECT_EQ(e.code(), EISDIR);
  }
  try {
    read_volume(dir.path() / "none.nrrd");
    FAIL() << "no error";
  } catch (const FileError& e) {
    EXPECT_EQ(e.code(), ENOENT);
  }
  // A file that is there but wrong is no FileError.
  std::ofstream(dir.path() / "bad.nrrd") << "not a nrrd\n";
  try {
    read_volume(dir.path() / "bad.nrrd");
    FAIL() << "no error";
  } catch (const FileError&) {
    FAIL() << "a FileError for a file's content";
  } catch (const Error&) {
  }
}

}  // namespace
}  // namespace imx::scene_json
