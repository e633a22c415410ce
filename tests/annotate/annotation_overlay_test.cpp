// A scene's annotations over its render (src/annotate/annotation_overlay.hpp): the ruler's pixels
// change where it projects and nowhere else, what lies behind the eye is not drawn, and a label
// reads what the annotation measures.
#include <gtest/gtest.h>

#include "annotate/annotation_overlay.hpp"
#include "have_font.hpp"

namespace imx {
namespace {

// Looking along +y from 400 mm at 128 x 128: a point at height z and depth 400 lands on row
// 64 - 64 (z / 400) / tan 15°.
Scene looking_along_y() {
  Scene s;
  s.camera.eye = {0, -400, 0};
  s.camera.target = {0, 0, 0};
  s.camera.up = {0, 0, 1};
  s.camera.fov_deg = 30;
  s.image.width = s.image.height = 128;
  return s;
}

int changed(const Image& a, const Image& b, int x0, int y0, int x1, int y1) {
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) n += a.at(x, y) != b.at(x, y);
  return n;
}

TEST(AnnotationOverlay, TheRulerIsDrawnWhereItProjects) {
  const Scene scene = looking_along_y();
  const Image blank(128, 128, glm::vec4(0, 0, 0, 1));
  Image drawn = blank;
  draw_annotations(drawn, scene, {{AnnotationKind::ruler, {{-30, 0, 40}, {30, 0, 40}}, "", ""}},
                   nullptr);
  // Row 40.1, columns 64 ± 17.9.
  for (int x = 48; x <= 80; ++x) {
    EXPECT_GT(drawn.at(x, 40).r, 0.5f) << x;
    EXPECT_NEAR(drawn.at(x, 40).r / kAnnotationColour[0], drawn.at(x, 40).g / kAnnotationColour[1],
                1e-4)
        << x;
  }
  EXPECT_EQ(changed(drawn, blank, 0, 0, 128, 34), 0);    // above it
  EXPECT_EQ(changed(drawn, blank, 0, 47, 128, 128), 0);  // below it
  EXPECT_EQ(changed(drawn, blank, 0, 0, 40, 128), 0);    // beyond its ends
  EXPECT_EQ(changed(drawn, blank, 88, 0, 128, 128), 0);
}

TEST(AnnotationOverlay, BehindTheEyeIsNotDrawn) {
  const Scene scene = looking_along_y();
  const Image blank(128, 128, glm::vec4(0, 0, 0, 1));
  Image drawn = blank;
  // Wholly behind the eye: nothing. From behind to in front: only the part in front.
  draw_annotations(drawn, scene, {{AnnotationKind::ruler, {{0, -500, 10}, {10, -450, 10}}, "", ""}},
                   nullptr);
  EXPECT_EQ(changed(drawn, blank, 0, 0, 128, 128), 0);
  draw_annotations(drawn, scene, {{AnnotationKind::ruler, {{0, -500, 0}, {0, 0, 0}}, "", ""}},
                   nullptr);
  EXPECT_GT(changed(drawn, blank, 60, 60, 68, 68), 0);  // its far end, at the centre
}

TEST(AnnotationOverlay, LabelsSayWhatItMeasures) {
  if (!test::have_font()) GTEST_SKIP() << "no annotation font (apt-get install fonts-dejavu-core)";
  const Scene scene = looking_along_y();
  const Image blank(128, 128, glm::vec4(0, 0, 0, 1));
  Image lines = blank, labelled = blank;
  const std::vector<Annotation> a = {{AnnotationKind::ruler, {{-30, 0, 0}, {0, 0, 0}}, "", "w"}};
  draw_annotations(lines, scene, a, nullptr);
  const TextRaster text(find_font(), 12);
  draw_annotations(labelled, scene, a, &text);
  // The label goes below and right of the last point (the centre): "w: 30.0 mm".
  EXPECT_GT(changed(labelled, lines, 64, 64, 128, 90), 20);
  EXPECT_EQ(changed(labelled, lines, 0, 0, 128, 60), 0);
}

}  // namespace
}  // namespace imx
