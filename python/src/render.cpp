// Scene.render, intermix.Renderer, available_methods: the engine on a worker thread, the GIL
// released, Ctrl-C cancelling.
#include "render.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <functional>
#include <thread>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/stl.h>

#include "annotate/keys.hpp"
#include "annotate/scene_colour_bars.hpp"

#include "arguments.hpp"
#include "core/parallel.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "scene.hpp"

namespace imx::python {
namespace {

constexpr int kMaxImageSide = 16384;  // as the scene loader's image.width / height
constexpr int kMaxSpp = 1024;         // as render.spp
constexpr auto kSignalPoll = std::chrono::milliseconds(50);

// Runs `work` on a thread of its own while the calling thread waits without the GIL. Every
// kSignalPoll the caller takes the GIL and runs Python's signal handlers (they run in the main
// thread only): when one raises (KeyboardInterrupt on Ctrl-C), `cancel` is set, the work is
// waited for (render() stops within a tile per thread) and the Python exception is raised.
// Exceptions of `work` are rethrown in the caller.
void run_interruptible(const std::function<void()>& work, std::atomic<bool>& cancel) {
  std::mutex mutex;
  std::condition_variable finished;
  bool done = false;
  std::exception_ptr error;
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    std::thread worker([&] {
      try {
        work();
      } catch (...) {
        error = std::current_exception();
      }
      std::lock_guard<std::mutex> lock(mutex);
      done = true;
      finished.notify_all();
    });
    std::unique_lock<std::mutex> lock(mutex);
    while (!finished.wait_for(lock, kSignalPoll, [&] { return done; })) {
      if (interrupted) continue;
      lock.unlock();
      {
        py::gil_scoped_acquire gil;
        // An exception a handler raised stays set in this thread until it is raised below.
        interrupted = PyErr_CheckSignals() != 0;
      }
      if (interrupted) cancel.store(true);
      lock.lock();
    }
    lock.unlock();
    worker.join();
  }
  if (interrupted) throw py::error_already_set();
  if (!error) return;
  try {
    std::rethrow_exception(error);
  } catch (const Cancelled&) {
    throw;
  } catch (const Error& e) {
    throw RenderFailure(e.what());
  }
}

std::string unavailable_method_message(std::string_view function, const std::string& method) {
  return fmt::format("{}: method '{}' is not available; this build has: {}", function, method,
                     fmt::join(available_methods(), ", "));
}

// The frame to render and its options, from the scene and the request (whose values
// render_request checked); ValueError for a method this build lacks.
Scene prepare(const Scene& scene, const RenderRequest& request, RenderOptions& options) {
  Scene frame = scene;
  if (request.width) frame.image.width = *request.width;
  if (request.height) frame.image.height = *request.height;
  options.method = request.method.value_or("");
  const std::string method = resolve_method(scene, options.method).name;  // "auto": by content
  if (default_spp(method) == 0)
    throw py::value_error(unavailable_method_message(request.function, method));
  if (request.spp) options.spp = *request.spp;
  if (request.threads) options.threads = *request.threads;
  return frame;
}

Image render_image(const Scene& scene, const RenderRequest& request, PyRenderer* renderer) {
  RenderOptions options;
  // The copy lives here, so its data is released in this thread, with the GIL.
  const Scene frame = prepare(scene, request, options);
  std::atomic<bool> cancel{false};
  options.cancel = &cancel;
  Image image;
  run_interruptible(
      [&] {
        if (renderer == nullptr) {
          image = render(frame, options);
          return;
        }
        std::lock_guard<std::mutex> lock(renderer->mutex);
        image = renderer->renderer.render(frame, options);
        std::lock_guard<std::mutex> stats_lock(renderer->stats_mutex);
        renderer->stats = renderer->renderer.last_stats();
        ++renderer->frames;
      },
      cancel);
  // As `intermix render --colorbar`: colour bars and legends of the visible objects, after it.
  if (request.colorbar)
    draw_keys(image, scene_colour_bars(frame), scene_legends(frame),
              {*request.colorbar, request.colorbar_scale, glm::vec3(frame.image.background)});
  return image;
}

RendererStats stats_of(PyRenderer& r) {
  std::lock_guard<std::mutex> lock(r.stats_mutex);
  return r.stats;
}

}  // namespace

std::optional<ColourBarPosition> colour_bar_argument(const py::handle& value,
                                                     const Argument& argument) {
  if (value.is_none()) return std::nullopt;
  if (py::isinstance<py::str>(value)) {
    const std::string name = text(value, argument);
    if (std::optional<ColourBarPosition> p = find_colour_bar_position(name)) return p;
    throw py::value_error(fmt::format("{}: {} '{}' is not one of {}", argument.function,
                                      argument.name, name,
                                      fmt::join(colour_bar_position_names(), ", ")));
  }
  if (!flag(value, argument)) return std::nullopt;
  return ColourBarPosition::top_right;
}

RenderRequest render_request(std::string_view function, const py::handle& method,
                             const py::handle& width, const py::handle& height,
                             const py::handle& spp, const py::handle& threads) {
  RenderRequest request;
  request.function = std::string(function);
  request.method = optional_text(method, {function, "method"});
  request.width = optional_int_in(width, {function, "width"}, 1, kMaxImageSide);
  request.height = optional_int_in(height, {function, "height"}, 1, kMaxImageSide);
  request.spp = optional_int_in(spp, {function, "spp"}, 1, kMaxSpp);
  const int root =
      static_cast<int>(std::lround(std::sqrt(static_cast<double>(request.spp.value_or(1)))));
  if (request.spp && root * root != *request.spp)
    throw py::value_error(
        fmt::format("{}: spp {} is not a perfect square in [1, {}] (1, 4, 9, 16, 25, ...)",
                    function, *request.spp, kMaxSpp));
  request.threads = optional_int_in(threads, {function, "threads"}, 0, kMaxThreads);
  return request;
}

py::object render_scene(const Scene& scene, const RenderRequest& request, PyRenderer* renderer) {
  return image_to_array(render_image(scene, request, renderer));
}

py::bytes preview_png(const Scene& scene, int side) {
  RenderRequest request;
  const int longer = std::max(scene.image.width, scene.image.height);
  if (longer > side) {
    const double scale = static_cast<double>(side) / longer;
    request.width = std::max(1, static_cast<int>(std::lround(scene.image.width * scale)));
    request.height = std::max(1, static_cast<int>(std::lround(scene.image.height * scale)));
  }
  request.spp = 1;
  const Image image = render_image(scene, request, nullptr);
  return py::bytes(encode_png(image, "preview"));
}

void bind_render(py::module_& m) {
  m.def("available_methods", &available_methods,
        "Names of the rendering methods this build implements (README, Methods).");
  m.def(
      "default_spp",
      [](const TextParameter& method_argument) {
        const std::string method = text(method_argument, {"default_spp", "method"});
        const int spp = default_spp(method);
        if (spp == 0) throw py::value_error(unavailable_method_message("default_spp", method));
        return spp;
      },
      py::arg("method"),
      "Samples per pixel `method` renders with when neither the scene nor the call sets them.");

  py::class_<RendererStats>(m, "RendererStats", "What the last frame of a Renderer reused.")
      .def_readonly("stages", &RendererStats::stages,
                    "Pipeline stages of the last frame (0: the method is not staged).")
      .def_readonly("stages_run", &RendererStats::stages_run,
                    "Of them, how many rendered their object again.")
      .def_readonly("stages_merged", &RendererStats::stages_merged,
                    "Deferred stages merged again (kept or new arrays).")
      .def_readonly("stream_bytes_per_pixel", &RendererStats::stream_bytes_per_pixel,
                    "Tile-local stage buffers, bytes per pixel of a tile.")
      .def_readonly("kept_bytes_per_pixel", &RendererStats::kept_bytes_per_pixel,
                    "Slab arrays kept for the next frame, bytes per pixel.")
      .def_readonly("recast_unchanged", &RendererStats::recast_unchanged,
                    "zslab-hybrid re-cast its last volume though it was unchanged.")
      .def("__repr__", [](const RendererStats& s) {
        return fmt::format(
            "RendererStats(stages={}, stages_run={}, stages_merged={}, "
            "stream_bytes_per_pixel={:g}, kept_bytes_per_pixel={:g}, recast_unchanged={})",
            s.stages, s.stages_run, s.stages_merged, s.stream_bytes_per_pixel,
            s.kept_bytes_per_pixel, s.recast_unchanged ? "True" : "False");
      });

  py::class_<PyRenderer, std::shared_ptr<PyRenderer>>(
      m, "Renderer",
      R"doc(Renders frame after frame, keeping what it can between them: with the zslab methods each
object's own slab array is kept, so after changing one object (a transfer function, a window,
a material) only that object is rendered again; the image is byte-identical to a fresh render.
Other methods render as Scene.render does. Volumes and meshes are recognised by identity: a
Scene keeps them across set() and add_*(), so pass the same Scene (or its copies).

Renderer(kept_budget=None): kept_budget bounds the kept arrays in bytes (default 512 MiB; the
largest are evicted first). One frame at a time: concurrent calls on one Renderer wait in turn.
)doc")
      .def(py::init([](const OptionalIntParameter& kept_budget) {
             auto r = std::make_shared<PyRenderer>();
             if (!kept_budget.is_none())
               r->renderer.set_kept_budget(static_cast<uint64_t>(
                   int_at_least(kept_budget, {"Renderer", "kept_budget"}, 0)));
             return r;
           }),
           py::arg("kept_budget") = py::none())
      .def(
          "render",
          [](PyRenderer& r, const SceneParameter& scene, const OptionalTextParameter& method,
             const OptionalIntParameter& width, const OptionalIntParameter& height,
             const OptionalIntParameter& spp, const OptionalIntParameter& threads) {
            const PyScene& s =
                instance_of<PyScene>(scene, {"Renderer.render", "scene"}, "an intermix.Scene");
            return render_scene(
                s.scene(), render_request("Renderer.render", method, width, height, spp, threads),
                &r);
          },
          py::arg("scene"), py::arg("method") = py::none(), py::arg("width") = py::none(),
          py::arg("height") = py::none(), py::arg("spp") = py::none(),
          py::arg("threads") = py::none(),
          "Renders `scene` as Scene.render does (same arguments, same image), reusing what "
          "earlier frames kept.")
      .def_property_readonly("stats", &stats_of,
                             "RendererStats of the last frame: stages, stages_run, ...")
      .def_property_readonly(
          "frames",
          [](PyRenderer& r) {
            std::lock_guard<std::mutex> lock(r.stats_mutex);
            return r.frames;
          },
          "Frames rendered so far.")
      .def_property(
          "kept_budget",
          [](PyRenderer& r) {
            py::gil_scoped_release release;
            std::lock_guard<std::mutex> lock(r.mutex);
            return r.renderer.kept_budget();
          },
          [](PyRenderer& r, const IntParameter& bytes) {
            const auto budget =
                static_cast<uint64_t>(int_at_least(bytes, {"Renderer", "kept_budget"}, 0));
            py::gil_scoped_release release;
            std::lock_guard<std::mutex> lock(r.mutex);
            r.renderer.set_kept_budget(budget);
          },
          "Bytes the kept slab arrays may take (0 keeps nothing).")
      .def(
          "clear",
          [](PyRenderer& r) {
            py::gil_scoped_release release;
            std::lock_guard<std::mutex> lock(r.mutex);
            r.renderer.clear();
          },
          "Drops every kept array.");
}

}  // namespace imx::python
