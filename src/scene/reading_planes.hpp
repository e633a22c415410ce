// The three reading planes the viewer adds to a scene built from files: axial, coronal and
// sagittal through the centre of its first volume, hidden until the user shows them.
#pragma once
#include <glm/vec2.hpp>
#include <nlohmann/json.hpp>

#include "intermix/scene.hpp"

namespace imx {

// The window a reading view or plane shows a volume through: the scene's "window" for it, else
// the initial-window rule (volume/display_window.hpp: the header's window when it shows the
// anatomy, else the 2nd to 98th percentile of the voxels above the background).
glm::dvec2 reading_window(const VolumeObject& volume);

// Plane objects for the document's "objects" (none when the scene has no volume): normals along
// the patient axes (LPS), radiological "up" (anterior for axial, superior otherwise), sized to
// the volume's box, windowed by reading_window. Names avoid the scene's own ("axial", else
// "axial-2", ...).
nlohmann::json reading_planes(const Scene& scene);

}  // namespace imx
