// CsgFrame: a scene's CSG expression made ready for one frame: primitives mapped to objects and
// volumes, the expression as a program, the clipping states, and the view the kernels read.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "csg/csg_expr.hpp"
#include "csg/csg_view.hpp"
#include "csg/state_table.hpp"
#include "frame/frame_setup.hpp"
#include "intermix/scene.hpp"

namespace imx {

class CsgFrame {
 public:
  // Throws imx::Error when the expression has more states than render.csg_max_states, or
  // nothing of it can show within the primitives' bounds. Without `with_states` the clipping
  // states are not built (the reference evaluates the expression). A scene without a csg block
  // has no primitives.
  CsgFrame(const Scene& scene, const FrameSetup& frame, bool with_states);

  CsgView view() const;
  const std::vector<CsgPrimitive>& primitives() const { return primitives_; }
  const CsgTableReport& report() const { return report_; }
  const CsgTable& table() const { return table_; }

 private:
  std::vector<CsgPrimitive> primitives_;
  CsgProgram program_;
  CsgTable table_;
  CsgTableReport report_;
  std::vector<int8_t> primitive_of_object_, primitive_of_volume_, volume_of_primitive_;
  std::vector<CsgMedium> medium_;
  PrimitiveMask geometric_ = 0, meshes_ = 0, with_medium_ = 0;
  float presence_threshold_ = 0.0f;
};

// The world-space bounding box of each primitive (a mesh's vertices, a volume's 8 hull corners).
std::vector<CsgBox> primitive_boxes(const Scene& scene, std::span<const CsgPrimitive> primitives);

}  // namespace imx
