// bench --change: times re-renders after one object edit, with stage outputs kept between frames.
#pragma once
#include <string>
#include <vector>

#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace imx::cli {

struct ChangeTiming {
  std::vector<double> ms;        // per timed re-render
  std::vector<double> fresh_ms;  // per fresh (stateless) render of the edited scene, interleaved
  int stages = 0;                // stages of the frame
  int stages_run = 0;            // stages the edit made render their object again
  int stages_merged = 0;         // deferred stages merged again
  double kept_bytes_per_pixel = 0.0;
};

// Loads the scene with `overrides` plus "objects.CHANGE" (CHANGE is OBJECT.key=value), shares
// the unchanged voxel and mesh data with `base` so stage keys can match, then alternates: render
// `base` (untimed), render the edited scene (timed), `frames` times, with one imx::Renderer;
// each round also times a fresh imx::render of the edited scene, for the ratio in one run.
ChangeTiming time_change(const Scene& base, const std::string& scene_file,
                         std::vector<std::string> overrides, const std::string& change,
                         const RenderOptions& options, int frames);

}  // namespace imx::cli
