// Streamlines (tractograms) and connectomes in world space (LPS, mm), as their files give them.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace imx {

// A named value per point or per streamline (TRK scalars and properties, TSF, TRX dpv/dps).
struct StreamlineValues {
  std::string name;
  std::vector<float> values;  // one per point (Streamlines::points) or per streamline
};

// A TRX group: a named subset of the streamlines, with the colour its file gives, if any.
struct StreamlineGroup {
  std::string name;
  std::vector<uint32_t> members;   // streamline indices, ascending
  std::optional<glm::vec3> color;  // linear RGB in [0, 1], decoded from the file's display colour
};

// Streamline i runs through points[offsets[i] .. offsets[i + 1]).
struct Streamlines {
  std::vector<glm::vec3> points;  // world LPS mm
  std::vector<uint32_t> offsets{0};
  std::vector<StreamlineValues> point_values;
  std::vector<StreamlineValues> streamline_values;
  std::vector<StreamlineGroup> groups;

  size_t count() const { return offsets.size() - 1; }
  size_t length(size_t i) const { return offsets[i + 1] - offsets[i]; }
};

// A connectome: nodes at positions and weighted edges between them (NiiVue's .jcon/.json,
// BrainNet Viewer's .node/.edge).
struct ConnectomeNode {
  std::string name;
  glm::vec3 position{0.0f};  // world LPS mm
  float value = 0.0f;        // colours the node through the node colour map
  float size = 1.0f;         // the file's size value (radius scale)
};

struct ConnectomeEdge {
  uint32_t a = 0, b = 0;  // node indices, a < b
  float weight = 0.0f;
};

// How NiiVue's connectome JSON asks to be drawn: each field as its file gives it, absent where
// it gives none (NiiVue's defaults then apply). Colour maps are NiiVue's names ("warm").
struct ConnectomeStyle {
  std::optional<std::string> name;
  std::optional<std::string> node_colormap;
  std::optional<std::string> node_colormap_negative;  // for nodes of negative value
  std::optional<float> node_min_color;                // node values mapped to the colour map's ends
  std::optional<float> node_max_color;
  std::optional<float> node_scale;  // sphere radius = size * node_scale (mm)
  std::optional<std::string> edge_colormap;
  std::optional<std::string> edge_colormap_negative;  // for edges of negative weight
  std::optional<float> edge_min;  // |weight| mapped to the colour map's ends; below: hidden
  std::optional<float> edge_max;
  std::optional<float> edge_scale;  // cylinder radius = |weight| * edge_scale (mm)
};

struct Connectome {
  std::vector<ConnectomeNode> nodes;
  std::vector<ConnectomeEdge> edges;  // every nonzero entry of the upper triangle
  ConnectomeStyle style;              // NiiVue's JSON only
};

}  // namespace imx
