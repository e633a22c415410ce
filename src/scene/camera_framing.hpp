// A camera that frames a scene's objects, looking at the patient from one of the six standard
// directions (LPS world: +x left, +y posterior, +z superior), for scenes that give no eye.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "intermix/scene.hpp"

namespace imx {

enum class PatientView { anterior, posterior, left, right, superior, inferior };

// The names as scene files and --view spell them, in PatientView's order.
const std::vector<std::string>& patient_view_names();
std::optional<PatientView> find_patient_view(std::string_view name);

// The world-space box of the scene's visible objects (every object when none is visible): the
// voxels a volume's transfer function shows (its whole grid for xray, or with `whole_grids`),
// mesh vertices, plane rectangles. A scene loaded by region (distributed) passes whole_grids,
// and a volume's grid is then its whole source: every process frames the same box. Empty
// (lo > hi) for a scene without objects.
struct WorldBox {
  glm::dvec3 lo{1e300}, hi{-1e300};
  bool empty() const { return lo.x > hi.x; }
};
WorldBox visible_bounds(const Scene& scene, bool whole_grids = false);

// `camera` (its fov_deg, projection) turned to look from `view` at the box's centre, superior up
// (anterior up for the superior and inferior views), at the distance where the whole box fits
// the image's aspect with a small margin; ortho_height fits it too. A scene without objects
// gets the view direction around the origin.
Camera framed_camera(const Camera& camera, const WorldBox& box, PatientView view, double aspect);

}  // namespace imx
