// Rendering from Python: the GIL released while the engine works, Ctrl-C cancelling it.
#pragma once
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "annotate/colour_bar.hpp"
#include "arguments.hpp"
#include "bindings.hpp"
#include "intermix/renderer.hpp"
#include "intermix/scene.hpp"

namespace imx::python {

// What a render call may change for one frame; unset values keep the scene's own.
struct RenderRequest {
  std::optional<std::string> method;
  std::optional<int> width, height, spp, threads;
  std::string function = "render";  // names the call in errors: "Scene.render"
  // Draw the scene's colour bars there (into a corner, or beside the image on a wider canvas).
  std::optional<ColourBarPosition> colorbar;
  double colorbar_scale = 1.0;  // of the bars' and legends' text and strips
};

// A render call's arguments, checked (TypeError, ValueError naming `function` and the
// argument): method a str, width and height in [1, 16384] as the scene's image, spp a perfect
// square in [1, 1024], threads in [0, 1024]; None keeps the scene's own.
// colorbar=: False or None (no bars), True (the top-right corner) or a position's name
// ("outside", ...: colour_bar.hpp); TypeError or ValueError naming the argument otherwise.
std::optional<ColourBarPosition> colour_bar_argument(const py::handle& value,
                                                     const Argument& argument);

RenderRequest render_request(std::string_view function, const py::handle& method,
                             const py::handle& width, const py::handle& height,
                             const py::handle& spp, const py::handle& threads);

// intermix.Renderer: an imx::Renderer (stage reuse between frames) used by one render at a time.
struct PyRenderer {
  Renderer renderer;
  std::mutex mutex;        // held by the rendering thread, never with the GIL
  std::mutex stats_mutex;  // guards stats and frames
  RendererStats stats;
  int frames = 0;
};

// Renders `scene` (through `renderer` when given, else imx::render) into an intermix.Image.
// Arguments are checked first (ValueError); the engine then runs on a worker thread while the
// caller waits without the GIL, waking every 50 ms to run Python's signal handlers: Ctrl-C sets
// the render's cancel flag, waits for it to stop and raises KeyboardInterrupt. A failing
// render raises RuntimeError with the library's message.
py::object render_scene(const Scene& scene, const RenderRequest& request, PyRenderer* renderer);

// The PNG a notebook shows for a scene: its own method at 1 sample per pixel, at most `side`
// pixels along the longer edge.
py::bytes preview_png(const Scene& scene, int side);

}  // namespace imx::python
