// intermix render SCENE.json -o OUT.png: one frame of a scene file; or of a scene built from
// volume, DICOM and mesh files (intermix render FLAIR.nii.gz -o f.png).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <optional>
#include <regex>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "annotate/annotation_overlay.hpp"
#include "annotate/keys.hpp"
#include "annotate/scene_colour_bars.hpp"
#include "commands.hpp"
#include "core/parallel.hpp"
#include "core/progress_bar.hpp"
#include "dist/bricked_render.hpp"
#include "dist/distributed_render.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "movie/movie_format.hpp"
#include "render_movie.hpp"
#include "scene_inputs.hpp"

namespace imx::cli {

namespace {

struct Options : SceneOptions {
  SceneInputs in;
  std::string scene, output, method;  // scene: the inputs, for messages
  std::string frame_range, frame_object;
  bool linear = false;
  bool colorbar = false;
  bool no_annotations = false;
  std::string colorbar_position = "top-right";
  double colorbar_scale = 1.0;
  bool distributed = false;
  std::string partition = "auto", report;
  int bricks = 0;  // 0: bricks only for a volume too large to hold
  bool lod = false;
  MovieShot movie;
};

// The scene of the inputs; --save-scene writes a built one, which renders the same image again.
// With `annotations`, the document's annotations go there.
Scene load_inputs(const Options& o, const std::vector<std::string>& overrides,
                  std::vector<Annotation>* annotations = nullptr) {
  SceneDocument document = load_scene_inputs(o.in, overrides);
  save_built_scene(o.in, document);
  if (annotations) *annotations = document.annotations();
  return std::move(document).take_scene();
}

// Loads, renders and writes one image, printing its notes and time. A scene with a volume too
// large to hold whole (or any, with --bricks N) is rendered brick by brick.
void render_one(const Options& o, const std::vector<std::string>& overrides,
                const std::string& output) {
  std::optional<SceneDocument> outline;
  std::vector<Annotation> annotations;
  Scene whole;
  if (o.bricks > 0 || o.lod) {
    outline.emplace(load_scene_outline(o.in, overrides));
  } else {
    try {
      whole = load_inputs(o, overrides, &annotations);
    } catch (const VolumeTooLarge& e) {
      if (!quiet()) std::fprintf(stderr, "intermix: note: %s: rendering in bricks\n", e.what());
      outline.emplace(load_scene_outline(o.in, overrides));
    }
  }
  if (outline) save_built_scene(o.in, *outline);
  const Scene& scene = outline ? outline->scene() : whole;
  print_notes(scene.notes);
  RenderOptions options;
  options.method = o.method;
  options.spp = o.spp;
  options.threads = o.threads;
  ProgressBar bar("render", show_progress());
  options.progress = [&bar](double f) { bar.update(f); };
  auto start = std::chrono::steady_clock::now();
  Image image;
  std::string method;
  try {
    if (outline) {
      // Levels of detail need bricks to vary over: at least kLodBricks.
      const int parts =
          o.bricks > 0 ? o.bricks : std::max(bricks_needed(scene), o.lod ? kLodBricks : 1);
      if (!o.method.empty() && !o.method.starts_with("zslab") && o.method != "auto" && !quiet())
        std::fprintf(stderr, "intermix: note: --method %s: a render in bricks uses zslab\n",
                     o.method.c_str());
      BrickLevelRule levels;
      if (o.lod) levels = [](size_t, int fitting) { return fitting; };
      if (o.lod && scene_pyramids(*outline).empty() && !quiet())
        std::fprintf(stderr,
                     "intermix: note: --lod: no volume is read from an OME-Zarr pyramid, so every "
                     "brick is full resolution (intermix convert X -o X.zarr builds one)\n");
      const BrickedFrame frame = render_in_bricks(*outline, parts, options, levels);
      image = frame.image;
      method = fmt::format("zslab in {} bricks", parts);
      if (o.lod) method += fmt::format(" (pyramid levels up to {})", frame.coarsest_level);
    } else {
      image = render(scene, options);
      const ResolvedMethod resolved = resolve_method(scene, o.method);
      method = resolved.reason.empty()
                   ? resolved.name
                   : fmt::format("{} (auto: {})", resolved.name, resolved.reason);
    }
  } catch (const Error& e) {
    throw Error(fmt::format("{}: {}", o.scene, e.what()));  // what the method refused
  }
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  bar.finish();
  // Annotations first: they are projected through the camera onto the render's own canvas,
  // which an "outside" key then widens.
  if (outline) annotations = outline->annotations();
  if (!o.no_annotations && !annotations.empty())
    draw_annotations(image, scene, annotations, annotation_font(image).get());
  if (o.colorbar) {
    const std::vector<ColourBar> bars = scene_colour_bars(scene);
    const std::vector<Legend> legends = scene_legends(scene);
    const ColourBarStyle style{*find_colour_bar_position(o.colorbar_position), o.colorbar_scale,
                               glm::vec3(scene.image.background)};
    const KeyPlacements drawn = draw_keys(image, bars, legends, style);
    const size_t wanted = distinct_colour_bars(bars).size() + legends.size();
    if (drawn.bars.size() + drawn.legends.size() < wanted && !quiet())
      std::fprintf(stderr,
                   "intermix: note: %zu of %zu colour bars and legends drawn: no room for more "
                   "in the image\n",
                   drawn.bars.size() + drawn.legends.size(), wanted);
  }
  write_png(image, output, o.linear);
  if (!quiet())
    std::fprintf(stderr, "intermix: %s: %dx%d with %s on %d threads in %.3f s -> %s\n",
                 o.scene.c_str(), image.width(), image.height(), method.c_str(),
                 resolve_thread_count(o.threads), seconds, output.c_str());
}

// --frame-range A:B: frame k of one volume object to the -o pattern's k-th name, one at a time
// (each frame's voxels replace the last's).
int render_frames(const Options& o, const std::vector<std::string>& overrides) {
  int first = 0, last = 0;
  char tail = 0;
  if (std::sscanf(o.frame_range.c_str(), "%d:%d%c", &first, &last, &tail) != 2 || first < 0 ||
      last < first)
    throw Error(fmt::format("--frame-range '{}': give A:B with 0 <= A <= B", o.frame_range));
  // The pattern: exactly one %d, %Nd or %0Nd, and no other %.
  const std::regex number("%0?[0-9]{0,2}d");
  const auto found = std::distance(std::sregex_iterator(o.output.begin(), o.output.end(), number),
                                   std::sregex_iterator());
  if (found != 1 || std::count(o.output.begin(), o.output.end(), '%') != 1)
    throw Error(fmt::format(
        "{}: with --frame-range, -o needs one frame number such as out_%03d.png", o.output));
  std::string object = o.frame_object;
  if (object.empty()) {
    const Scene probe = load_inputs(o, overrides);
    if (probe.volumes.size() != 1)
      throw Error(fmt::format("{}: {} volume objects; name one with --frame-object", o.scene,
                              probe.volumes.size()));
    object = probe.volumes.front().name;
  }
  for (int k = first; k <= last; ++k) {
    std::vector<std::string> with_frame = overrides;
    with_frame.push_back(fmt::format("objects.{}.source.frame={}", object, k));
    char name[4096];
    std::snprintf(name, sizeof name, o.output.c_str(), k);
    render_one(o, with_frame, name);
  }
  return 0;
}

}  // namespace

Command add_render(CLI::App& app) {
  auto o = std::make_shared<Options>();
  add_scene_inputs(app, o->in);
  app.add_option("-o,--output", o->output,
                 "output PNG; with --orbit or --sweep a movie: .mp4 (H.264), .webm (VP9) or .mkv "
                 "(FFV1, lossless)")
      ->required();
  app.add_option("--method", o->method,
                 "rendering method (default: the scene's, else auto: the fastest within reach of "
                 "the best image for the scene's content)");
  add_scene_options(app, *o);
  app.add_flag("--linear", o->linear, "write linear instead of sRGB-encoded colour");
  app.add_flag("--colorbar", o->colorbar,
               "draw a colour bar (name, units, ticks) for each visible colour-mapped object: "
               "volumes' transfer functions, planes with a colour map or threshold; and a legend "
               "(names and colours) for each label map and tractogram coloured by group");
  app.add_option("--colorbar-position", o->colorbar_position,
                 "where --colorbar draws the bars: top-right (default), top-left, bottom-right, "
                 "bottom-left, or outside (beside the image, on a canvas widened to fit them)")
      ->check(CLI::IsMember(colour_bar_position_names()));
  app.add_option("--colorbar-scale", o->colorbar_scale,
                 "size of --colorbar's bars and legends: text and strips times this (default 1: "
                 "text about a 36th of the image's height)")
      ->check(in_range(0.25, 8.0));
  app.add_flag("--no-annotations", o->no_annotations,
               "leave out the scene's annotations (rulers, angles, ROIs), drawn by default with "
               "what each measures");
  std::string no_mpi;
  const bool mpi = distributed_available(&no_mpi);
  app.add_flag("--distributed", o->distributed,
               mpi ? "split the render over the processes of this MPI job "
                     "(mpirun -np R intermix render ... --distributed)"
                   : "unavailable: " + no_mpi);
  app.add_option("--partition", o->partition,
                 "with --distributed: objects, bricks or auto (default: auto)")
      ->check(CLI::IsMember({"objects", "bricks", "auto"}));
  app.add_option("--frame-range", o->frame_range,
                 "A:B: render frames A to B of a multi-frame (4-D) volume, one PNG each; -o then "
                 "names them with a printf number such as out_%03d.png");
  app.add_option("--frame-object", o->frame_object,
                 "with --frame-range: the volume object whose frames run (default: the scene's "
                 "only volume)");
  app.add_option("--bricks", o->bricks,
                 "render in N bricks, loading one at a time (default: only a volume too large to "
                 "hold whole, past 2^31 voxels or half the memory budget, in as many as it needs)")
      ->check(CLI::Range(1, 4096));
  app.add_flag("--lod", o->lod,
               "levels of detail: each brick of an OME-Zarr pyramid reads the coarsest level whose "
               "voxel fits its pixels (faster; not full resolution)");
  app.add_option("--report", o->report,
                 "with --distributed: write timings, bytes exchanged and memory per rank (JSON)");
  add_movie_options(app, o->movie);
  return [o]() {
    o->scene = o->in.label();
    const std::vector<std::string> overrides = input_overrides(o->in, o->with_size());
    if (!o->distributed && (o->report.size() || o->partition != "auto"))
      throw Error("--partition and --report apply only with --distributed");
    if (o->distributed && o->colorbar) throw Error("--colorbar does not apply with --distributed");
    if (o->distributed && o->bricks > 0)
      throw Error("--bricks does not apply with --distributed (use --partition bricks)");
    if (o->distributed && o->lod) throw Error("--lod does not apply with --distributed");
    if (o->distributed && !o->frame_range.empty())
      throw Error("--frame-range does not apply with --distributed");
    if (o->distributed && !o->in.is_scene_file())
      throw Error("--distributed renders a scene file; write one with --save-scene first");
    if (o->movie.wanted()) {
      for (const auto& [given, name] :
           {std::pair{o->distributed, "--distributed"},
            std::pair{!o->frame_range.empty(), "--frame-range"},
            std::pair{o->bricks > 0, "--bricks"}, std::pair{o->lod, "--lod"},
            std::pair{o->linear, "--linear"}})
        if (given)
          throw Error(fmt::format("{} does not apply to a movie (--orbit, --sweep)", name));
      RenderOptions options;
      options.method = o->method;
      options.spp = o->spp;
      options.threads = o->threads;
      return render_movie(o->in, overrides, o->movie, options, {o->colorbar, !o->no_annotations},
                          o->output);
    }
    if (o->movie.frames > 0) throw Error("--frames applies only with --sweep");
    if (o->movie.fps != 24.0 || o->movie.degrees != 360.0)
      throw Error("--fps and --orbit-degrees apply only to a movie (--orbit, --sweep)");
    if (find_movie_format(o->output))
      throw Error(
          fmt::format("{}: a movie needs --orbit N or --sweep AXIS; without them render "
                      "writes one PNG",
                      o->output));
    if (o->distributed) {
      DistributedRequest request;
      request.scene = o->scene;
      request.overrides = overrides;
      request.method = o->method;
      request.spp = o->spp;
      request.threads = o->threads;
      request.partition = parse_partition_mode(o->partition);
      request.output = o->output;
      request.linear = o->linear;
      request.report = o->report;
      request.progress = show_progress();
      return render_distributed(request, [](const std::string& message) {
        std::fprintf(stderr, "intermix: error: %s\n", message.c_str());
      });
    }
    if (!o->frame_range.empty()) return render_frames(*o, overrides);
    if (!o->frame_object.empty()) throw Error("--frame-object applies only with --frame-range");
    render_one(*o, overrides, o->output);
    return 0;
  };
}

}  // namespace imx::cli
