// The VTK peer for `intermix bench --vtk`: finding vtk_peer.py, rewriting the scene into files
// it can read, running it under xvfb-run and reading back its timing.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "intermix/scene.hpp"

namespace imx::cli {

struct PeerRun {
  std::filesystem::path peer;          // vtk_peer.py
  std::filesystem::path scene_file;    // the scene as given to bench
  std::vector<std::string> overrides;  // --set assignments, applied to the peer's copy too
  const Scene* scene = nullptr;        // that scene loaded with the same overrides
  std::string mode = "cpu";            // the peer's --mode: cpu or gpu
  int frames = 5;
  double sample_distance_mm = 0.0;
  bool notes = true;  // say on stderr what the peer cannot draw as intermix does
};

// VTK's ray caster draws a volume's voxels at origin + index * spacing along its own axes and
// ignores the grid's direction, so an oblique or flipped grid (an oblique MR, a NIfTI stored RAS)
// would be drawn elsewhere and turned: another image, timed as if it were the same. The peer is
// given the scene in the first volume's frame instead: its voxels on the axes from the origin
// (mirrored along i first when the grid is left-handed), the camera and every other object moved
// by the same rigid motion, so that VTK draws the image intermix does. A sheared grid (gantry
// tilt) has no such frame (`square` false): the scene stays in world space and VTK draws the
// grid unsheared.
struct PeerFrame {
  glm::dmat4 world_to_frame{1.0};  // rigid: world mm -> the frame's mm
  glm::dvec3 spacing{1.0};         // the voxels' pitch along i, j, k
  bool mirror_i = false;           // the voxels are written with each row reversed
  bool square = false;             // the grid's axes are perpendicular: the frame applies
};

PeerFrame peer_frame(const glm::dmat4& index_to_world, glm::ivec3 dims);

struct PeerTiming {
  double ms_median = 0.0, ms_min = 0.0, ms_max = 0.0;
  bool empty_image = false;  // VTK drew nothing: the time measures no rendering
  double peak_rss_mib = 0.0;
  // Reading the files plus the first render (uploads, gradient and normal caches): VTK's time
  // to its first image; 0 when the peer does not say.
  double first_image_ms = 0.0;
};

// --peer's default: shared/peers/vtk_peer.py in the nearest folder above this executable, else
// above the scene file (the repository layout puts ../shared beside the checkout). Empty when
// neither has one.
std::filesystem::path find_vtk_peer(const std::filesystem::path& scene_file);

// The peer's sample distance for `scene`: render.step_mm when set, else the smallest voxel
// pitch of its volumes (1 mm without volumes).
double peer_sample_distance(const Scene& scene);

// Writes a copy of the scene for the peer into `dir`: every volume becomes a MetaImage and
// every mesh an OBJ, both already placed in the first volume's frame (PeerFrame; so their
// "transform" is dropped: the peer reads no transforms), and the camera with them; everything
// else is kept. Returns the new scene file.
std::filesystem::path write_peer_scene(const PeerRun& run, const std::filesystem::path& dir);

// Throws imx::Error when `peer` is not a file or xvfb-run, /usr/bin/python3 or its vtk and numpy
// modules are missing (naming scripts/install-deps --with-peers). Bench calls it before timing.
void check_vtk_peer(const std::filesystem::path& peer);

// Runs the peer (checked by check_vtk_peer) on the scene at the scene's image size, in a
// temporary folder removed afterwards. Throws imx::Error when the peer fails, with its last
// output lines.
PeerTiming run_vtk_peer(const PeerRun& run);

}  // namespace imx::cli
