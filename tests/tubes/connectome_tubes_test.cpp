// Connectomes as tubes: which nodes and edges show and how (NiiVue's rules), and the spheres
// and tubes they become, hit where their geometry says, in their own colours.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/colour.hpp"
#include "presets/colormap.hpp"
#include "tubes/connectome_primitives.hpp"
#include "tubes/tube_fragments.hpp"
#include "tubes/tube_geometry.hpp"

namespace imx {
namespace {

// Four nodes on a square in the z = 0 plane, edges along its sides of weights 1, -3, 0.5, 5.
Connectome square() {
  Connectome c;
  c.nodes = {{"a", {0, 0, 0}, 2.0f, 1.0f},
             {"b", {40, 0, 0}, 3.0f, 2.0f},
             {"c", {40, 40, 0}, -3.0f, 1.0f},
             {"d", {0, 40, 0}, 0.5f, 1.0f}};
  c.edges = {{0, 1, 1.0f}, {1, 2, -3.0f}, {2, 3, 0.5f}, {0, 3, 5.0f}};
  return c;
}

TEST(ConnectomePrimitives, NiiVuesRulesForSizeColourAndThreshold) {
  ConnectomeLook look;  // NiiVue's defaults: nodes 0..4, edges 2..6, scales 3 and 1
  look.node_colormap = Colormap::grey;
  look.node_colormap_negative = Colormap::hot;
  look.edge_colormap = Colormap::grey;
  look.edge_colormap_negative = Colormap::jet;
  look.node_min = 1.0f;  // node d (0.5) falls below and is hidden
  const ConnectomePrimitives p = connectome_primitives(square(), look);
  ASSERT_EQ(p.spheres.size(), 3u);
  EXPECT_EQ(p.hidden_nodes, 1u);
  EXPECT_FLOAT_EQ(p.spheres[0].radius, 1.0f * look.node_scale);
  EXPECT_FLOAT_EQ(p.spheres[1].radius, 2.0f * look.node_scale);
  // The grey map gives display greys, decoded (docs/colour.md).
  EXPECT_NEAR(p.spheres[0].color.r, srgb_decode((2.0f - 1.0f) / (4.0f - 1.0f)), 1e-6f);
  EXPECT_NEAR(p.spheres[1].color.r, srgb_decode((3.0f - 1.0f) / (4.0f - 1.0f)), 1e-6f);
  // Negative: |value| through the negative map.
  const glm::vec3 hot = colormap_rgb(Colormap::hot, (3.0f - 1.0f) / 3.0f);
  EXPECT_NEAR(glm::length(p.spheres[2].color - hot), 0.0f, 1e-6f);
  // Edges: |weight| 1 and 0.5 are below edge_min 2: hidden. -3 and 5 show, radius |w| * scale.
  ASSERT_EQ(p.tubes.size(), 2u);
  EXPECT_EQ(p.hidden_edges, 2u);
  EXPECT_FLOAT_EQ(p.tubes[0].radius, 3.0f);
  EXPECT_FLOAT_EQ(p.tubes[1].radius, 5.0f);
  const glm::vec3 jet = colormap_rgb(Colormap::jet, (3.0f - 2.0f) / 4.0f);
  EXPECT_NEAR(glm::length(p.tubes[0].color - jet), 0.0f, 1e-6f);
  EXPECT_NEAR(p.tubes[1].color.r, srgb_decode((5.0f - 2.0f) / 4.0f), 1e-6f);
  EXPECT_FLOAT_EQ(p.largest_radius, 6.0f);
  // Above the top: the top colour; an empty range: the top colour too.
  EXPECT_FLOAT_EQ(connectome_map_position(9.0f, 2.0f, 6.0f), 1.0f);
  EXPECT_FLOAT_EQ(connectome_map_position(0.0f, 2.0f, 2.0f), 1.0f);
}

TEST(ConnectomePrimitives, NiiVueColourMapNamesMapToTheClosestOrNone) {
  EXPECT_EQ(connectome_colormap("warm"), Colormap::red_yellow);
  EXPECT_EQ(connectome_colormap("winter"), Colormap::blue_lightblue);
  EXPECT_EQ(connectome_colormap("viridis"), Colormap::viridis);
  EXPECT_EQ(connectome_colormap("gray"), Colormap::grey);
  EXPECT_EQ(connectome_colormap("cold-hot"), Colormap::cold_hot);
  EXPECT_FALSE(connectome_colormap("batlow"));
}

StreamlineObject object_of(const Connectome& c, const ConnectomeLook& look) {
  StreamlineObject o;
  o.name = "net";
  o.connectome = std::make_shared<const Connectome>(c);
  o.connectome_look = look;
  auto centres = std::make_shared<Streamlines>();
  for (const ConnectomeNode& n : c.nodes) centres->points.push_back(n.position);
  o.streamlines = std::move(centres);
  return o;
}

TEST(ConnectomeTubes, SpheresAndTubesAreHitOnTheirSurfacesInTheirColours) {
  ConnectomeLook look;
  look.node_min = 0.0f;
  look.edge_min = 0.0f;
  look.edge_max = 6.0f;
  look.edge_scale = 0.2f;  // thinner than every sphere, whose centres then show the sphere
  const StreamlineObject o = object_of(square(), look);
  const ConnectomePrimitives p = connectome_primitives(*o.connectome, look);
  const TubeGeometry tubes(o);
  ASSERT_TRUE(tubes.is_connectome());
  ASSERT_EQ(tubes.primitive_count(), p.tubes.size() + p.spheres.size());
  std::vector<TubeHit> hits(8);
  // Down through each sphere's centre: entry and exit at its radius, its colour.
  for (size_t i = 0; i < p.spheres.size(); ++i) {
    const ConnectomeSphere& s = p.spheres[i];
    const Ray ray{s.center + glm::vec3(0.0f, 0.0f, 100.0f), {0.0f, 0.0f, -1.0f}};
    const size_t n = tubes.nearest_hits(ray, 0.0f, 1e9f, hits);
    ASSERT_GE(n, 2u) << i;
    EXPECT_NEAR(hits[0].t, 100.0f - s.radius, 1e-3f) << i;
    EXPECT_NEAR(hits[n - 1].t, 100.0f + s.radius, 1e-3f) << i;
    EXPECT_EQ(tubes.primitive_color(hits[0].segment), s.color) << i;
  }
  // Across each tube at its middle, beside the spheres: entry and exit at its radius.
  for (size_t i = 0; i < p.tubes.size(); ++i) {
    const ConnectomeTube& t = p.tubes[i];
    const Ray ray{0.5f * (t.a + t.b) + glm::vec3(0.0f, 0.0f, 100.0f), {0.0f, 0.0f, -1.0f}};
    ASSERT_EQ(tubes.nearest_hits(ray, 0.0f, 1e9f, hits), 2u) << i;
    EXPECT_NEAR(hits[0].t, 100.0f - t.radius, 1e-3f) << i;
    EXPECT_NEAR(hits[1].t, 100.0f + t.radius, 1e-3f) << i;
    EXPECT_EQ(tubes.primitive_color(hits[0].segment), t.color) << i;
    EXPECT_LT(hits[0].normal.z * -1.0f, 0.0f);  // the entry faces the ray
  }
  // Past a tube's side: nothing.
  const ConnectomeTube& t = p.tubes[0];
  const glm::vec3 side = glm::normalize(glm::cross(t.b - t.a, glm::vec3(0, 0, 1)));
  const Ray beside{0.5f * (t.a + t.b) + side * (t.radius + 0.05f) + glm::vec3(0, 0, 100),
                   {0, 0, -1}};
  EXPECT_EQ(tubes.nearest_hits(beside, 0.0f, 1e9f, hits), 0u);
}

TEST(ConnectomeTubes, FragmentsCarryThePrimitivesColourAndOpacity) {
  ConnectomeLook look;
  look.node_colormap = Colormap::grey;
  look.node_min = 0.0f;
  Connectome one;
  one.nodes = {{"n", {0, 0, 0}, 1.0f, 1.0f}};
  StreamlineObject o = object_of(one, look);
  o.shading.enabled = false;
  o.opacity = 0.4f;
  const TubeGeometry tubes(o);
  const TubeLook tube_look = make_tube_look(o, tubes);
  std::vector<Fragment> out;
  append_tube_fragments(tube_look, Ray{{0, 0, 50}, {0, 0, -1}}, 1e9f, 3, {}, out);
  ASSERT_EQ(out.size(), 2u);  // in and out of the sphere
  const float a = tube_fragment_alpha(0.4f), grey = srgb_decode(1.0f / 4.0f);  // a display grey
  for (const Fragment& f : out) {
    EXPECT_EQ(f.object, 3u);
    EXPECT_NEAR(f.color.a, a, 1e-6f);
    EXPECT_NEAR(f.color.r, grey * a, 1e-5f);
  }
  EXPECT_NEAR(out[0].t, 50.0f - look.node_scale, 1e-3f);
  EXPECT_NEAR(out[1].t, 50.0f + look.node_scale, 1e-3f);
}

}  // namespace
}  // namespace imx
