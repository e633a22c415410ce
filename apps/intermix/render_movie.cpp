#include "render_movie.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "annotate/annotation_overlay.hpp"
#include "annotate/scene_colour_bars.hpp"
#include "core/parallel.hpp"
#include "core/progress_bar.hpp"
#include "intermix/error.hpp"
#include "intermix/renderer.hpp"
#include "movie/movie_format.hpp"
#include "movie/orbit_cameras.hpp"
#include "movie/slice_sweep.hpp"
#include "movie/write_movie.hpp"

namespace imx::cli {

void add_movie_options(CLI::App& app, MovieShot& shot) {
  app.add_option("--orbit", shot.orbit,
                 "N: a turntable movie of N frames, the camera turning about the scene's up axis "
                 "through its target (-o turn.mp4, .webm or .mkv)")
      ->check(CLI::Range(1, 100000));
  app.add_option("--orbit-degrees", shot.degrees, "with --orbit: how far it turns (default: 360)")
      ->check(in_range(-36000.0, 36000.0));
  app.add_option("--sweep", shot.sweep,
                 "axial, coronal or sagittal: a movie of an MPR plane moving through its volume "
                 "from one end to the other (the scene's plane of that axis, or one added)")
      ->check(CLI::IsMember(sweep_axis_names()));
  app.add_option("--frames", shot.frames,
                 "with --sweep: how many positions, one frame each (default: one per voxel slice)")
      ->check(CLI::Range(1, 100000));
  app.add_option("--fps", shot.fps, "with --orbit or --sweep: frames per second (default: 24)")
      ->check(in_range(1.0, 240.0));
}

namespace {

// The document the movie renders, with a sweep's plane found or added: a scene built from files
// looks at a sweep's plane from the reading view's side unless --view says otherwise.
SceneDocument load_movie_scene(const SceneInputs& in, const std::vector<std::string>& overrides,
                               const MovieShot& shot, std::optional<SliceSweep>& sweep) {
  SceneInputs inputs = in;
  const std::optional<SweepAxis> axis = find_sweep_axis(shot.sweep);
  if (axis && inputs.view.empty() && !inputs.is_scene_file()) inputs.view = sweep_view(*axis);
  SceneDocument document = load_scene_inputs(inputs, overrides);
  if (axis) sweep = plan_slice_sweep(document, *axis, shot.frames);
  save_built_scene(in, document);  // with the sweep's plane: it sweeps the same again
  if (!axis) return document;
  const Scene& scene = document.scene();
  const PlaneObject& plane = scene.planes[static_cast<size_t>(sweep->plane)];
  const glm::dvec3 look = glm::normalize(scene.camera.target - scene.camera.eye);
  if (std::abs(glm::dot(look, plane.normal)) < 0.5)
    sweep->notes.push_back(fmt::format(
        "--sweep {}: the camera sees plane '{}' at a glancing angle; --view {} faces it",
        shot.sweep, plane.name, sweep_view(*axis)));
  return document;
}

}  // namespace

std::unique_ptr<TextRaster> annotation_font(const Image& image) {
  try {
    return std::make_unique<TextRaster>(find_font(),
                                        std::max(12, std::min(image.width(), image.height()) / 40));
  } catch (const Error& e) {
    if (!quiet())
      std::fprintf(stderr, "intermix: note: annotations drawn without labels: %s\n", e.what());
    return nullptr;
  }
}

int render_movie(const SceneInputs& in, const std::vector<std::string>& overrides,
                 const MovieShot& shot, const RenderOptions& options, const Overlays& overlays,
                 const std::string& output) {
  if (shot.orbit > 0 && !shot.sweep.empty())
    throw Error("--orbit and --sweep: give one (a movie either turns or sweeps)");
  if (shot.orbit > 0 && shot.frames > 0)
    throw Error("--frames applies only with --sweep (--orbit N gives the frame count)");
  if (shot.orbit == 0 && shot.degrees != 360.0)
    throw Error("--orbit-degrees applies only with --orbit");
  const MovieFormat& format = movie_format_for(output);
  std::optional<SliceSweep> sweep;
  const SceneDocument document = load_movie_scene(in, overrides, shot, sweep);
  const Scene& scene = document.scene();
  print_notes(scene.notes);
  if (sweep) print_notes(sweep->notes);
  const std::vector<Camera> cameras = shot.orbit > 0
                                          ? orbit_cameras(scene.camera, shot.orbit, shot.degrees)
                                          : std::vector<Camera>{};
  const int frames = sweep ? static_cast<int>(sweep->centres.size()) : shot.orbit;
  const std::vector<ColourBar> bars =
      overlays.colour_bars ? scene_colour_bars(scene) : std::vector<ColourBar>{};
  const std::vector<Annotation> annotations =
      overlays.annotations ? document.annotations() : std::vector<Annotation>{};
  std::unique_ptr<TextRaster> font;
  if (!annotations.empty()) font = annotation_font(Image(scene.image.width, scene.image.height));

  Renderer renderer;
  Scene shown = scene;
  ProgressBar bar(sweep ? "sweep" : "orbit", show_progress());
  MovieOptions movie;
  movie.fps = shot.fps;
  movie.progress = [&bar](double f) { bar.update(f); };
  const auto start = std::chrono::steady_clock::now();
  try {
    write_movie(
        output, scene.image.width, scene.image.height, frames,
        [&](int k, const std::function<void(double)>& progress) {
          if (sweep)
            shown.planes[static_cast<size_t>(sweep->plane)].center = sweep->centres[k];
          else
            shown.camera = cameras[static_cast<size_t>(k)];
          RenderOptions frame_options = options;
          frame_options.progress = progress;
          Image image = renderer.render(shown, frame_options);
          // As `render` draws them: annotations through this frame's camera, then the bars.
          if (!annotations.empty()) draw_annotations(image, shown, annotations, font.get());
          if (!bars.empty()) draw_colour_bars(image, bars);
          return image;
        },
        movie);
  } catch (const Error& e) {
    if (std::string(e.what()).starts_with(output)) throw;  // names the movie already
    throw Error(fmt::format("{}: {}", in.label(), e.what()));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  bar.finish();
  if (!quiet()) {
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(output, ec);
    std::fprintf(stderr,
                 "intermix: %s: %d frames %dx%d (%s, %.3g fps) with %s on %d threads in %.3f s "
                 "(%.3f s a frame) -> %s (%.1f kB)\n",
                 in.label().c_str(), frames, scene.image.width, scene.image.height,
                 format.codec.c_str(), shot.fps, resolve_method(scene, options.method).name.c_str(),
                 resolve_thread_count(options.threads), seconds, seconds / frames, output.c_str(),
                 ec ? 0.0 : bytes / 1000.0);
  }
  return 0;
}

}  // namespace imx::cli
