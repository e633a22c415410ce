// Vertex welding: one id per distinct vertex, numbered in order of first occurrence.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace imx::detail {

struct Weld {
  std::vector<uint32_t> id;     // per input vertex: its welded vertex
  std::vector<uint32_t> first;  // per welded vertex: the first input vertex that has it
};

// Welds vertices whose positions (and colours, when `colors` is not empty) have equal bits,
// +0 and -0 alike. Welded ids follow the input order of each one's first vertex. Sorts in
// parallel; the result is the same whatever the thread count.
Weld weld_vertices(std::span<const glm::vec3> positions, std::span<const glm::vec3> colors = {});

}  // namespace imx::detail
