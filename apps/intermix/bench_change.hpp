// bench --change: times re-renders after one object edit, with stage outputs kept between frames.
#pragma once
#include <string>
#include <vector>

#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx::cli {

struct ChangeTiming {
  std::vector<double> ms;  // per timed re-render
  int stages = 0;          // stages of the frame
  int stages_run = 0;      // stages the edit made run again
};

// Loads the scene with `overrides` plus "objects.CHANGE" (CHANGE is OBJECT.key=value), shares
// the unchanged voxel and mesh data with `base` so stage keys can match, then alternates: render
// `base` (untimed), render the edited scene (timed), `frames` times, with one imx::Renderer.
ChangeTiming time_change(const Scene& base, const std::string& scene_file,
                         std::vector<std::string> overrides, const std::string& change,
                         const RenderOptions& options, int frames);

}  // namespace imx::cli
