#include "tubes/connectome_primitives.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/geometric.hpp>

#include "presets/colormap.hpp"

namespace imx {
namespace {

constexpr float kEndInset = 0.05f;  // of a tube's radius, where a sphere hides its end

// NiiVue's names for the maps intermix has, or has one close to: "warm" (orange to yellow) as
// red-yellow, "winter" (blue to green) as blue-lightblue.
constexpr std::pair<std::string_view, Colormap> kNiivueNames[] = {
    {"warm", Colormap::red_yellow},
    {"redyell", Colormap::red_yellow},
    {"winter", Colormap::blue_lightblue},
    {"gray", Colormap::grey}};

}  // namespace

std::optional<Colormap> connectome_colormap(std::string_view name) {
  for (const auto& [niivue, map] : kNiivueNames)
    if (name == niivue) return map;
  return find_colormap(name);
}

std::string_view connectome_colormap_names() {
  return "NiiVue's warm, winter, redyell, gray, hot, inferno, viridis, plasma, jet; intermix's "
         "grey, cold-hot, red-yellow, blue-lightblue";
}

float connectome_map_position(float value, float low, float high) {
  if (!(low < high)) return 1.0f;
  if (value < low) return -1.0f;
  return std::min((value - low) / (high - low), 1.0f);
}

ConnectomePrimitives connectome_primitives(const Connectome& connectome,
                                           const ConnectomeLook& look) {
  ConnectomePrimitives out;
  out.spheres.reserve(connectome.nodes.size());
  std::vector<float> sphere_radius(connectome.nodes.size(), 0.0f);  // 0: not shown
  for (const ConnectomeNode& node : connectome.nodes) {
    const float radius = node.size * look.node_scale;
    const bool negative = node.value < 0.0f;
    const float t = connectome_map_position(std::abs(node.value), look.node_min, look.node_max);
    if (!(radius > 0.0f) || t < 0.0f) {
      ++out.hidden_nodes;
      continue;
    }
    sphere_radius[static_cast<size_t>(&node - connectome.nodes.data())] = radius;
    out.spheres.push_back(
        {node.position, radius,
         colormap_rgb(negative ? look.node_colormap_negative : look.node_colormap, t)});
    out.largest_radius = std::max(out.largest_radius, radius);
  }
  out.tubes.reserve(connectome.edges.size());
  for (const ConnectomeEdge& edge : connectome.edges) {
    const float magnitude = std::abs(edge.weight);
    const float radius = magnitude * look.edge_scale;
    const float t = connectome_map_position(magnitude, look.edge_min, look.edge_max);
    glm::vec3 a = connectome.nodes[edge.a].position, b = connectome.nodes[edge.b].position;
    if (!(radius > 0.0f) || t < 0.0f || a == b) {
      ++out.hidden_edges;
      continue;
    }
    // A round end inside a node's sphere as large as itself would coincide with it (the two
    // fight for every pixel): it ends a little inside instead, behind the sphere's surface.
    const glm::vec3 inward = kEndInset * radius * glm::normalize(b - a);
    const float length = glm::length(b - a);
    if (sphere_radius[edge.a] >= radius && length > 4.0f * kEndInset * radius) a += inward;
    if (sphere_radius[edge.b] >= radius && length > 4.0f * kEndInset * radius) b -= inward;
    out.tubes.push_back(
        {a, b, radius,
         colormap_rgb(edge.weight < 0.0f ? look.edge_colormap_negative : look.edge_colormap, t)});
    out.largest_radius = std::max(out.largest_radius, radius);
  }
  return out;
}

}  // namespace imx
