// Connectome readers (io/connectome/): the input goes whole through the JSON sniff and NiiVue's
// connectome JSON reader, then through BrainNet's reader as a .node file, or, when it holds
// kEdgeMarker, as a .node file (before it) and its .edge matrix (after it). A connectome read
// must have nodes at finite positions and edges (a < b) between them of finite, nonzero weight.
#include <cmath>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "harness.hpp"
#include "intermix/streamlines.hpp"
#include "io/connectome/brainnet.hpp"
#include "io/connectome/jcon.hpp"

namespace {

inline constexpr std::string_view kEdgeMarker = "\n@@EDGE@@\n";

void check_connectome(const imx::Connectome& c) {
  if (c.nodes.empty()) __builtin_trap();
  for (const imx::ConnectomeNode& n : c.nodes)
    if (!std::isfinite(n.position.x) || !std::isfinite(n.position.y) ||
        !std::isfinite(n.position.z) || !std::isfinite(n.value) || !std::isfinite(n.size))
      __builtin_trap();
  for (const imx::ConnectomeEdge& e : c.edges)
    if (e.a >= e.b || e.b >= c.nodes.size() || !std::isfinite(e.weight) || e.weight == 0.0f)
      __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const std::string_view input = as_view(data, size);
  imx::detail::looks_like_connectome_json(input);
  std::vector<std::string> notes;
  try {
    check_connectome(imx::detail::read_jcon(dir.write("in.jcon", input), notes));
    accepted("jcon");
  } catch (const std::exception& e) {
    refused(e);
  }
  const Split parts = split_at(input, kEdgeMarker);
  const std::filesystem::path node = dir.write("in.node", parts.head);
  std::optional<std::filesystem::path> edge;
  if (parts.found) edge = dir.write("in.edge", parts.tail);
  try {
    check_connectome(imx::detail::read_brainnet(node, edge, notes));
    accepted("brainnet");
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
