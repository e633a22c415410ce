// A colour volume (VolumeData::colours: NIfTI RGB24, DICOM RGB) renders in its own colours in
// every method, its TF giving only opacity, and an MPR plane through it shows its colours.
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "core/colour.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "volume/colour_grid.hpp"

namespace imx {
namespace {

constexpr int kSide = 32;
const glm::u8vec3 kRed(220, 20, 10), kGreen(15, 230, 40);

// 32^3 voxels of 1 mm centred on the origin: the half x < 16 `left` coloured, the rest `right`.
// With colours, the scalars are their luminance; without, the scalar is 255 in the left half
// and 0 elsewhere (a mask of where the left half lies).
std::shared_ptr<VolumeData> halves(bool colours) {
  auto data = std::make_shared<VolumeData>();
  data->dims = glm::ivec3(kSide);
  data->index_to_world = glm::translate(glm::dmat4(1.0), glm::dvec3(-(kSide - 1) / 2.0));
  const size_t n = static_cast<size_t>(kSide) * kSide * kSide;
  std::vector<uint8_t> scalar(n);
  auto rgb = std::make_shared<ColourVoxels>();
  rgb->rgb.resize(3 * n);
  for (size_t i = 0; i < n; ++i) {
    const bool left = static_cast<int>(i % kSide) < kSide / 2;
    const glm::u8vec3 c = left ? kRed : kGreen;
    for (int k = 0; k < 3; ++k) rgb->rgb[3 * i + k] = c[k];
    scalar[i] = colours ? colour_luminance(c.r, c.g, c.b) : (left ? 255 : 0);
  }
  data->voxels = std::move(scalar);
  if (colours) data->colours = std::move(rgb);
  return data;
}

Scene scene_of(std::shared_ptr<VolumeData> data, float opacity_at_white) {
  Scene scene;
  scene.image.width = 24;
  scene.image.height = 24;
  scene.image.background = glm::vec4(0.0f);  // a pixel's alpha is then what it shows
  scene.camera.projection = Projection::orthographic;
  scene.camera.ortho_height = 40.0;
  VolumeObject v;
  v.name = "rgb";
  v.data = std::move(data);
  v.index_to_world = v.data->index_to_world;
  // The look a colour volume gets by default: opacity rising with the luminance, white TF.
  v.transfer_function.points = {{0.0, glm::vec4(1.0f, 1.0f, 1.0f, 0.0f)},
                                {255.0, glm::vec4(1.0f, 1.0f, 1.0f, opacity_at_white)}};
  scene.volumes.push_back(v);
  scene.order.push_back({ObjectKind::volume, 0});
  return scene;
}

glm::vec3 linear(glm::u8vec3 c) {
  return {srgb_decode(c.r / 255.0f), srgb_decode(c.g / 255.0f), srgb_decode(c.b / 255.0f)};
}

Image render_with(const Scene& scene, const char* method) {
  RenderOptions options;
  options.method = method;
  options.threads = 1;
  return render(scene, options);
}

// Where the left half shows, from renders of its mask: 1 where a pixel sees only voxels of the
// left half (x <= 15), 0 where only voxels of the right half (x >= 16) or none, -1 (not checked)
// where it sees the voxels between, whose colours blend.
std::vector<int> left_half_pixels() {
  Scene scene = scene_of(halves(false), 1.0f);
  // Opaque only where the mask's trilinear value is 255: no voxel of the right half is near.
  scene.volumes[0].transfer_function.points = {{254.9, glm::vec4(1.0f, 1.0f, 1.0f, 0.0f)},
                                               {255.0, glm::vec4(1.0f, 1.0f, 1.0f, 1.0f)}};
  const Image only_left = render_with(scene, "reference");
  // Opaque wherever a voxel of the left half is near.
  scene.volumes[0].transfer_function.points = {{0.0, glm::vec4(1.0f, 1.0f, 1.0f, 0.0f)},
                                               {0.1, glm::vec4(1.0f, 1.0f, 1.0f, 1.0f)}};
  const Image near_left = render_with(scene, "reference");
  std::vector<int> where;
  for (size_t i = 0; i < only_left.size(); ++i)
    where.push_back(only_left.data()[i].a > 0.99f ? 1 : near_left.data()[i].a < 0.01f ? 0 : -1);
  return where;
}

// Every nearly opaque pixel inside the left half's image has the left colour, every one inside
// the right half's the right colour, and there are many of each.
void expect_halves(const Image& image, const std::vector<int>& left, const std::string& what,
                   glm::vec3 left_rgb, glm::vec3 right_rgb, float tolerance) {
  int lefts = 0, rights = 0, wrong = 0;
  for (size_t i = 0; i < image.size(); ++i) {
    const glm::vec4 p = image.data()[i];
    if (p.a < 0.98f || left[i] < 0) continue;  // outside the volume's image, or at the edge
    const glm::vec3 want = left[i] == 1 ? left_rgb : right_rgb;
    ++(left[i] == 1 ? lefts : rights);
    const glm::vec3 got = glm::vec3(p) / p.a;
    if (glm::any(glm::greaterThan(glm::abs(got - want), glm::vec3(tolerance))) && wrong++ < 4)
      ADD_FAILURE() << what << ": pixel " << i << " is (" << got.r << ", " << got.g << ", " << got.b
                    << "), want (" << want.r << ", " << want.g << ", " << want.b << ")";
  }
  EXPECT_EQ(wrong, 0) << what;
  EXPECT_GT(lefts, 40) << what << ": pixels checked in the left half";
  EXPECT_GT(rights, 40) << what << ": pixels checked in the right half";
}

TEST(ColourVolumeRender, EveryMethodShowsTheVoxelsColours) {
  const std::vector<int> left = left_half_pixels();
  const Scene scene = scene_of(halves(true), 1.0f);
  for (const char* method : {"reference", "mdvr", "zslab", "zslab-hybrid", "peel", "dfb", "dfb-sfm",
                             "kbuffer", "kbuffer-ofm", "wboit", "mboit", "csg"}) {
    // Unshaded emission-absorption of one colour: the pixel is that colour once opaque.
    expect_halves(render_with(scene, method), left, method, linear(kRed), linear(kGreen), 0.02f);
  }
}

TEST(ColourVolumeRender, PostClassificationAndShadingKeepTheColours) {
  const std::vector<int> left = left_half_pixels();
  Scene scene = scene_of(halves(true), 1.0f);
  scene.render.classification = "post";
  for (const char* method : {"reference", "mdvr", "zslab-hybrid"})
    expect_halves(render_with(scene, method), left, std::string(method) + " post", linear(kRed),
                  linear(kGreen), 0.02f);
  // Lit, the voxels' colour is what is lit (specular light adds white): red stays red.
  scene = scene_of(halves(true), 1.0f);
  scene.volumes[0].shading.enabled = true;
  for (const char* method : {"reference", "mdvr", "zslab-hybrid"}) {
    const Image image = render_with(scene, method);
    int reds = 0, greens = 0;
    for (size_t i = 0; i < image.size(); ++i) {
      const glm::vec4 p = image.data()[i];
      if (p.a < 0.98f || left[i] < 0) continue;
      const bool red = p.r > p.g + 0.2f, green = p.g > p.r + 0.2f;
      EXPECT_TRUE(left[i] == 1 ? red : green) << method << " lit pixel " << i;
      reds += red, greens += green;
    }
    EXPECT_GT(reds, 40) << method;
    EXPECT_GT(greens, 40) << method;
  }
}

TEST(ColourVolumeRender, AnMprPlaneShowsTheVoxelsColours) {
  const std::vector<int> left = left_half_pixels();
  Scene scene = scene_of(halves(true), 0.0f);  // the volume itself invisible: only the plane
  PlaneObject plane;
  plane.name = "mpr";
  plane.normal = {0, -1, 0};
  plane.up = {0, 0, 1};
  plane.size = {60, 60};
  plane.volume = 0;
  plane.window = {40.0, 80.0};  // a grey window would show luminance, not these colours
  scene.planes.push_back(plane);
  scene.order.push_back({ObjectKind::plane, 0});
  for (const char* method : {"reference", "mdvr", "zslab", "zslab-hybrid", "peel", "wboit"})
    expect_halves(render_with(scene, method), left, std::string(method) + " plane", linear(kRed),
                  linear(kGreen), 1e-3f);
}

}  // namespace
}  // namespace imx
