// intermix serve SCENE.json | FILE...: the interactive viewer in the browser (docs/viewer.md).
#include <cstdio>
#include <filesystem>
#include <map>
#include <system_error>

#include <fmt/format.h>

#include "commands.hpp"
#include "core/parallel.hpp"
#include "dist/bricked_render.hpp"
#include "intermix/limits.hpp"
#include "intermix/render.hpp"
#include "scene/reading_planes.hpp"
#include "scene_inputs.hpp"
#include "server/http_server.hpp"
#include "server/viewer_session.hpp"
#include "server/viewer_state.hpp"

#ifndef IMX_WEB_DIR
#define IMX_WEB_DIR "web"
#endif

namespace imx::cli {

namespace {

// The viewer's page: PREFIX/share/intermix/web beside an installed program (cmake --install),
// else the source tree's web/ the build was configured from.
std::string default_web_dir() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / "share" / "intermix" / "web";
    if (fs::is_regular_file(installed / "index.html", ec)) return installed.string();
  }
  return IMX_WEB_DIR;
}

// Frames finer than a scene shown at coarse pyramid levels (SessionOptions::full_resolution):
// the document's OME-Zarr sources at "level": "auto" or "view" taken from level 0, rendered in
// bricks as `intermix render` renders a volume too large to hold. Step s reads each brick s levels
// finer than the level that fits its pixels, and always finer than the level shown; the step whose
// bricks all read level 0 is the last.
decltype(server::SessionOptions::full_resolution) full_resolution_frames(const SceneDocument& shown,
                                                                         int threads) {
  // The level each "auto" or "view" source is shown at: the one whose grid the scene holds.
  std::map<size_t, int> shown_level;
  const nlohmann::json& objects = shown.json()["objects"];
  for (size_t k = 0; k < objects.size(); ++k) {
    const auto source = objects[k].find("source");
    if (source != objects[k].end() && source->is_object() &&
        (source->value("level", nlohmann::json()) == "auto" ||
         source->value("level", nlohmann::json()) == "view"))
      shown_level[k] = -1;
  }
  if (!shown_level.empty()) {
    nlohmann::json json = shown.json();
    for (const auto& [k, level] : shown_level) json["objects"][k]["source"].erase("level");
    const SceneDocument fine = outline_of(std::move(json), shown.origin(), shown.base_dir());
    for (const PyramidLevels& p : scene_pyramids(fine)) {
      if (!shown_level.count(p.object)) continue;
      const Scene& scene = shown.scene();
      const glm::ivec3 dims =
          scene.volumes[static_cast<size_t>(scene.order[p.object].index)].source_dims;
      for (size_t level = 0; level < p.dims.size(); ++level)
        if (p.dims[level] == dims) shown_level[p.object] = static_cast<int>(level);
    }
  }
  return [origin = shown.origin(), base_dir = shown.base_dir(), threads, shown_level](
             const nlohmann::json& document, int width, int height, int step,
             const std::atomic<bool>& cancel) {
    nlohmann::json json = document;
    for (const auto& [k, level] : shown_level) json["objects"][k]["source"].erase("level");
    json["image"]["width"] = width;
    json["image"]["height"] = height;
    const SceneDocument outline = outline_of(std::move(json), origin, base_dir);
    RenderOptions options;
    options.spp = document.contains("render") ? document["render"].value("spp", 0) : 0;
    options.threads = threads;
    options.cancel = &cancel;
    const BrickLevelRule levels = [&](size_t object, int fitting) {
      const auto shown_at = shown_level.find(object);
      if (shown_at == shown_level.end()) return 0;
      return std::max(0, std::min(fitting, shown_at->second - 1) - step);
    };
    const BrickedFrame frame = render_in_bricks(
        outline, std::max(bricks_needed(outline.scene()), kLodBricks), options, levels);
    return server::SessionOptions::Refinement{frame.image, frame.coarsest_level == 0};
  };
}

}  // namespace

Command add_serve(CLI::App& app) {
  struct Options : SceneOptions {
    SceneInputs in;
    std::string method, bind = "127.0.0.1", web;
    std::vector<std::string> allowed_origins;
    int port = 8080;
    double budget_ms = 45.0;
    int max_image_side = 2048;
  };
  auto o = std::make_shared<Options>();
  add_scene_inputs(app, o->in);
  app.add_option("--port", o->port, "TCP port (0: any free one, printed)")
      ->check(in_range(0, 65535));
  app.add_option("--bind", o->bind,
                 "address to listen on (default 127.0.0.1; for another machine use an SSH tunnel)");
  app.add_option("--method", o->method,
                 "rendering method (default: the scene's render.method, else zslab, csg for CSG)");
  app.add_option("--spp", o->spp,
                 "samples per pixel still frames converge to (default: the scene's, else 4)")
      ->check(in_range(1, 64));
  app.add_option("--frame-budget-ms", o->budget_ms,
                 "time a frame may take while the user moves (resolution adapts; default 45)")
      ->check(in_range(1, 10000));
  app.add_option("--max-image-side", o->max_image_side,
                 "largest side of a still frame: the page asks for its canvas's size times the "
                 "screen's pixel ratio, scaled down to this (default 2048)")
      ->check(in_range(16, 16384));
  app.add_option("--web", o->web,
                 "folder of the page (index.html, viewer.css, js/*.js; default: "
                 "PREFIX/share/intermix/web when installed, else the source tree's web/)");
  app.add_option("--allow-origin", o->allowed_origins,
                 "an origin (http://name:port) a page may come from besides the viewer's own "
                 "address, and whose name the browser may use as Host (repeatable; default: IP "
                 "addresses and localhost only)");
  add_scene_options(app, *o, kSizeOption | kThreadsOption | kSetOption);
  return [o]() {
    const std::vector<std::string> overrides = input_overrides(o->in, o->with_size());
    // A volume too large to hold: its OME-Zarr pyramid's finest level that fits.
    bool coarse = false;
    SceneDocument document = [&] {
      try {
        return load_scene_inputs(o->in, overrides);
      } catch (const VolumeTooLarge& e) {
        if (o->in.is_scene_file())
          throw Error(std::string(e.what()) +
                      "; the viewer shows an OME-Zarr pyramid's level that fits with \"source\": "
                      "{\"level\": \"auto\"} (intermix convert X -o X.zarr builds one)");
        coarse = true;
        return load_scene_inputs(o->in, overrides, true);
      }
    }();
    print_notes(document.scene().notes);  // what loading chose; later parses read no file again
    // A scene from files: saved in the current folder as scene.viewer-N.json.
    std::filesystem::path saves_beside = "scene.json";
    if (o->in.is_scene_file()) {
      saves_beside = o->in.inputs[0];
    } else {
      const nlohmann::json planes = reading_planes(document.scene());
      document.edit([&](nlohmann::json& json) {
        for (const nlohmann::json& plane : planes) json["objects"].push_back(plane);
      });
    }
    save_built_scene(o->in, document);
    server::SessionOptions session_options;
    if (coarse) session_options.full_resolution = full_resolution_frames(document, o->threads);
    server::ViewerState state = server::viewer_state(std::move(document), saves_beside);
    for (size_t i = 0; i < state.initial_windows.size(); ++i)  // a header window refused
      if (!state.initial_windows[i].note.empty() && !quiet())
        std::fprintf(stderr, "intermix serve: %s: %s\n", state.scene().volumes[i].name.c_str(),
                     state.initial_windows[i].note.c_str());
    session_options.method = o->method;
    session_options.spp = o->spp;
    session_options.threads = o->threads;
    session_options.moving_budget_ms = o->budget_ms;
    session_options.max_image_side = o->max_image_side;
    session_options.log = !quiet();
    server::ViewerSession session(std::move(state), std::move(session_options));
    server::ServerOptions server_options;
    server_options.bind = o->bind;
    server_options.port = static_cast<uint16_t>(o->port);
    server_options.web_dir = o->web.empty() ? default_web_dir() : o->web;
    server_options.allowed_origins = o->allowed_origins;
    {
      server::HttpServer server(session, server_options);
      std::printf("intermix serve: %s\n", server.url().c_str());
      std::fflush(stdout);
      if (!quiet())
        std::fprintf(stderr,
                     "intermix serve: %s with %s, converging to %d spp on %d threads; open the "
                     "address above in a browser, Ctrl+C stops\n",
                     o->in.label().c_str(), session.method().c_str(), session.spp(),
                     resolve_thread_count(o->threads));
      server.run();
      session.stop();  // nothing may send into the network thread once it is gone
    }
    if (!quiet()) std::fprintf(stderr, "intermix serve: stopped\n");
    return 0;
  };
}

}  // namespace imx::cli
