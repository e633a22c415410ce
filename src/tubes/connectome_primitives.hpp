// A connectome's spheres and tubes: which nodes and edges show, how large and in what colour,
// by NiiVue's rules (its connectome drawing: radius from size and weight, a value below the
// range's low end hidden, negative values through the negative colour map).
#pragma once
#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "intermix/scene.hpp"

namespace imx {

struct ConnectomeSphere {
  glm::vec3 center{0.0f};
  float radius = 0.0f;
  glm::vec3 color{0.0f};  // linear RGB
};

struct ConnectomeTube {
  // The two nodes' centres; an end whose node shows a sphere at least as large as the tube
  // moved 5% of the radius inward, so that its round cap lies inside the sphere.
  glm::vec3 a{0.0f}, b{0.0f};
  float radius = 0.0f;
  glm::vec3 color{0.0f};
};

struct ConnectomePrimitives {
  std::vector<ConnectomeTube> tubes;      // the shown edges, in the connectome's order
  std::vector<ConnectomeSphere> spheres;  // the shown nodes, in order
  size_t hidden_edges = 0;                // below edge_min, or of zero radius
  size_t hidden_nodes = 0;                // below node_min, or of zero radius
  float largest_radius = 0.0f;            // of every sphere and tube shown
};

// The colour map a connectome's field names: NiiVue's "warm", "winter", "redyell", "gray",
// "hot", "inferno", "viridis", "plasma" and "jet" as the closest of intermix's maps, or one of
// intermix's own names (presets/colormap.hpp); nothing for any other name.
std::optional<Colormap> connectome_colormap(std::string_view name);
// The names connectome_colormap takes, for messages.
std::string_view connectome_colormap_names();

// The colour-map position of `value` for a range [low, high]: NiiVue's (value - low) /
// (high - low) clamped to at most 1, or 1 where low >= high; negative where the value lies
// below low (hidden).
float connectome_map_position(float value, float low, float high);

ConnectomePrimitives connectome_primitives(const Connectome& connectome,
                                           const ConnectomeLook& look);

}  // namespace imx
