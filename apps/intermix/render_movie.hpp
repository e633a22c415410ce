// intermix render ... --orbit N | --sweep AXIS -o MOVIE: a turntable or a slice sweep as a movie
// (src/movie/), one render per frame.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "annotate/text_raster.hpp"
#include "intermix/image.hpp"
#include "intermix/render.hpp"
#include "scene_inputs.hpp"

namespace imx::cli {

struct MovieShot {
  int orbit = 0;           // frames of a turn about the scene's up axis (0: no orbit)
  double degrees = 360.0;  // of the turn
  std::string sweep;       // "axial", "coronal" or "sagittal" ("": no sweep)
  int frames = 0;          // of a sweep (0: one per voxel slice)
  double fps = 24.0;
  bool wanted() const { return orbit > 0 || !sweep.empty(); }
};

// Adds --orbit, --orbit-degrees, --sweep, --frames and --fps.
void add_movie_options(CLI::App& app, MovieShot& shot);

// What render draws over each image besides the render.
struct Overlays {
  bool colour_bars = false;
  bool annotations = true;  // the scene's rulers, angles and ROIs
};

// The font annotations over `image` are labelled with; null (with a note) when none is found,
// and then their lines are drawn alone.
std::unique_ptr<TextRaster> annotation_font(const Image& image);

// Renders the movie `shot` asks for to `output` (its extension chooses the format), with a
// progress bar and one line of what was written; each frame gets `overlays`.
int render_movie(const SceneInputs& in, const std::vector<std::string>& overrides,
                 const MovieShot& shot, const RenderOptions& options, const Overlays& overlays,
                 const std::string& output);

}  // namespace imx::cli
