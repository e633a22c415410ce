// A slice sweep: an MPR plane moved through its volume from one end to the other, one frame per
// position (intermix render --sweep axial -o sweep.mp4).
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "intermix/scene.hpp"
#include "scene/scene_document.hpp"

namespace imx {

enum class SweepAxis { axial, coronal, sagittal };

// "axial", "coronal", "sagittal", in SweepAxis's order.
const std::vector<std::string>& sweep_axis_names();
std::optional<SweepAxis> find_sweep_axis(std::string_view name);

// The patient direction a reading view of the axis looks from (radiological: the patient's left
// on the image's right): inferior for axial, anterior for coronal, left for sagittal.
const char* sweep_view(SweepAxis axis);

struct SliceSweep {
  int plane = -1;                   // index into the document's scene's planes
  std::vector<glm::dvec3> centres;  // the plane's centre in each frame (world, LPS)
  std::vector<std::string> notes;   // what the sweep chose for the user
};

// The sweep of the first visible plane of the document's scene that faces along `axis` and shows
// a volume; without one, a plane of that axis through the first volume is added to `document`
// (sized and windowed as the viewer's reading planes) and that volume's own rendering hidden, as
// `notes` say. The centres run through the plane's volume along its normal from the first voxel
// centre to the last: `frames` of them, or with frames 0 one per voxel slice. Throws imx::Error
// for a scene without a volume.
SliceSweep plan_slice_sweep(SceneDocument& document, SweepAxis axis, int frames = 0);

}  // namespace imx
