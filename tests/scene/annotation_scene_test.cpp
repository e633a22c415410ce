// The scene's top-level "annotations" (src/scene/annotation_parser.cpp): what parses, in which
// space, and the one error naming the JSON path for each kind of bad geometry.
#include <gtest/gtest.h>

#include "intermix/scene.hpp"
#include "scene/scene_document.hpp"
#include "scene_fixture.hpp"

namespace imx {
namespace {

using test::parse_error;

// The document's parsed annotations.
std::vector<Annotation> parse(const std::string& text, const std::vector<std::string>& set = {}) {
  return SceneDocument::from_text(text, "scene.json", {}, set).annotations();
}

std::string scene(const std::string& annotations, const std::string& space = "LPS") {
  return R"({"space": ")" + space + R"(", "objects": [
    {"name": "ct", "type": "volume", "source": {"phantom": "ct-head", "size": 16}},
    {"name": "ball", "type": "mesh", "source": {"primitive": "sphere", "radius": 10}}],
    "annotations": )" +
         annotations + "}";
}

TEST(AnnotationScene, ParsesEveryKind) {
  const std::vector<Annotation> s = parse(scene(R"([
    {"kind": "ruler", "points": [[0, 0, 0], [3, 4, 0]], "label": "width"},
    {"kind": "angle", "points": [[1, 0, 0], [0, 0, 0], [0, 1, 0]]},
    {"kind": "ellipse", "points": [[0, 0, 5], [4, 0, 5], [0, 2, 5]], "volume": "ct"},
    {"kind": "polygon", "points": [[0, 0, 1], [4, 0, 1], [4, 3, 1], [0, 3, 1]]}])"));
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0].kind, AnnotationKind::ruler);
  EXPECT_EQ(s[0].label, "width");
  EXPECT_EQ(s[1].kind, AnnotationKind::angle);
  EXPECT_EQ(s[2].kind, AnnotationKind::ellipse);
  EXPECT_EQ(s[2].volume, "ct");
  EXPECT_EQ(s[3].points.size(), 4u);
  EXPECT_EQ(s[3].points[2], glm::dvec3(4, 3, 1));
  EXPECT_TRUE(parse(scene("[]")).empty());
}

TEST(AnnotationScene, RasPointsAreReadIntoLps) {
  const std::vector<Annotation> s =
      parse(scene(R"([{"kind": "ruler", "points": [[1, 2, 3], [4, 5, 6]]}])", "RAS"));
  EXPECT_EQ(s[0].points[0], glm::dvec3(-1, -2, 3));
  EXPECT_EQ(s[0].points[1], glm::dvec3(-4, -5, 6));
}

TEST(AnnotationScene, BadAnnotationsNameTheirPath) {
  EXPECT_CONTAINS(parse_error(scene(R"({"kind": "ruler"})")), "scene.json: annotations: ");
  EXPECT_CONTAINS(parse_error(scene(R"([{"kind": "circle", "points": []}])")),
                  "annotations[0].kind");
  EXPECT_CONTAINS(parse_error(scene(R"([{"kind": "ruler", "points": [[0, 0, 0]]}])")),
                  "annotations[0].points: a ruler has 2 points, not 1");
  EXPECT_CONTAINS(parse_error(scene(R"([{"kind": "ruler", "points": [[0, 0, 0], [1, 2]]}])")),
                  "annotations[0].points[1]");
  EXPECT_CONTAINS(
      parse_error(scene(R"([{"kind": "ruler", "points": [[0, 0, 0], [1, 2, 1e300]]}])")),
      "annotations[0].points[1]");
  EXPECT_CONTAINS(
      parse_error(scene(R"([{"kind": "ruler", "points": [[0, 0, 0], [1, 1, 1]], "color": 1}])")),
      "annotations[0].color: unknown key");
  EXPECT_CONTAINS(parse_error(scene(R"([{"kind": "angle", "points": [[0, 0, 0], [0, 0, 0],
                                        [1, 0, 0]]}])")),
                  "annotations[0].points: an angle's arms");
  EXPECT_CONTAINS(parse_error(scene(R"([{"kind": "ellipse", "points": [[0, 0, 0], [2, 0, 0],
                                        [4, 0, 0]]}])")),
                  "annotations[0].points: an ellipse's semi-axes");
  EXPECT_CONTAINS(parse_error(scene(R"([{"kind": "polygon", "points": [[0, 0, 0], [1, 0, 0],
                                        [2, 0, 0]]}])")),
                  "annotations[0].points: the polygon encloses no area");
  EXPECT_CONTAINS(parse_error(scene(R"([{"kind": "polygon", "points": [[0, 0, 0], [4, 0, 0],
                                        [4, 4, 0], [0, 4, 2]]}])")),
                  "annotations[0].points[");
  EXPECT_CONTAINS(parse_error(scene(R"([{"kind": "ellipse", "points": [[0, 0, 0], [2, 0, 0],
                                        [0, 1, 0]], "volume": "ball"}])")),
                  "annotations[0].volume: 'ball' is a mesh, not a volume");
  EXPECT_CONTAINS(parse_error(scene(R"([{"kind": "ellipse", "points": [[0, 0, 0], [2, 0, 0],
                                        [0, 1, 0]], "volume": "cx"}])")),
                  "no volume named 'cx'");
  EXPECT_CONTAINS(parse_error(scene(R"([{"kind": "ruler", "points": [[0, 0, 0], [2, 0, 0]],
                                        "volume": "ct"}])")),
                  "annotations[0].volume: a ruler takes no volume");
  EXPECT_CONTAINS(parse_error(scene(R"([{"kind": "ruler", "points": [[0, 0, 0], [2, 0, 0]],
                                        "label": ")" +
                                    std::string(201, 'x') + R"("}])")),
                  "annotations[0].label: 201 bytes");
}

TEST(AnnotationScene, PointAndCountCaps) {
  std::string many = "[";
  for (size_t i = 0; i <= kMaxPolygonPoints; ++i)
    many += (i ? ", [" : "[") + std::to_string(std::cos(i * 0.01)) + ", " +
            std::to_string(std::sin(i * 0.01)) + ", 0]";
  EXPECT_CONTAINS(parse_error(scene(R"([{"kind": "polygon", "points": )" + many + "]}]")),
                  "a polygon has 3 to 256 points, not 257");
  std::string list = "[";
  for (size_t i = 0; i <= kMaxAnnotations; ++i)
    list += std::string(i ? ", " : "") + R"({"kind": "ruler", "points": [[0, 0, 0], [1, 0, 0]]})";
  EXPECT_CONTAINS(parse_error(scene(list + "]")), "annotations: 1001 annotations, more than");
}

TEST(AnnotationScene, SetReachesAnAnnotation) {
  const std::vector<Annotation> s =
      parse(scene(R"([{"kind": "ruler", "points": [[0, 0, 0], [3, 4, 0]]}])"),
            {"annotations[0].points[1]=[6,8,0]"});
  EXPECT_EQ(s[0].points[1], glm::dvec3(6, 8, 0));
}

}  // namespace
}  // namespace imx
