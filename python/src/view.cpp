// Scene.show and intermix.View: the viewer of `intermix serve` inside this process, on 127.0.0.1
// with a token of its own, showing the Scene's document: what Python changes reaches the pages,
// and what a page changes reaches the Scene (PyScene::pull). In Jupyter the view is an iframe.
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <thread>

#include <fmt/format.h>

#include "arguments.hpp"
#include "bindings.hpp"
#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "scene.hpp"
#include "server/http_server.hpp"
#include "server/viewer_session.hpp"
#include "server/viewer_state.hpp"

#ifndef IMX_WEB_DIR
#define IMX_WEB_DIR "web"
#endif

namespace imx::python {
namespace {

constexpr std::string_view kShow = "Scene.show";

// The viewer's page: $IMX_WEB_DIR, else the package's own copy (intermix/web, where pip and
// cmake --install put it), else the source tree this module was built from.
std::filesystem::path page_folder() {
  namespace fs = std::filesystem;
  if (const char* env = std::getenv("IMX_WEB_DIR"); env != nullptr && *env != '\0') return env;
  const py::object package = py::module_::import("intermix");
  if (py::hasattr(package, "__file__")) {
    const fs::path beside =
        fs::path(package.attr("__file__").cast<std::string>()).parent_path() / "web";
    std::error_code ec;
    if (fs::is_regular_file(beside / "index.html", ec)) return beside;
  }
  return IMX_WEB_DIR;
}

// One view: its session (shared with the Scene's link), the server and its network thread.
class PyView {
 public:
  PyView(PyScene& scene, int width, int height) : width_(width), height_(height) {
    SceneDocument document = scene.scene_document();
    const std::filesystem::path saves = scene.file().empty() ? "scene.json" : scene.file();
    server::SessionOptions options;
    options.log = false;
    session_ = std::make_shared<server::ViewerSession>(server::viewer_state(document, saves),
                                                       std::move(options));
    server::ServerOptions server_options;
    server_options.port = 0;
    server_options.web_dir = page_folder();
    server_options.stop_on_signals = false;  // Ctrl-C (interrupting the kernel) is Python's
    server_ = std::make_unique<server::HttpServer>(*session_, server_options);
    url_ = server_->url();
    thread_ = std::thread([this] { server_->run(); });
    scene.attach(session_, session_->document().second);
  }
  ~PyView() { close(); }
  PyView(const PyView&) = delete;
  PyView& operator=(const PyView&) = delete;

  void close() {
    if (!server_) return;
    // The server's threads may need the GIL to let go of numpy arrays (keep_alive): wait for
    // them without it.
    std::optional<py::gil_scoped_release> release;
    if (PyGILState_Check()) release.emplace();
    server_->stop();
    if (thread_.joinable()) thread_.join();
    session_->stop();
    server_.reset();
    session_.reset();  // the Scene's link lapses with it
  }
  bool open() const { return server_ != nullptr; }
  const std::string& url() const { return url_; }
  int width() const { return width_; }
  int height() const { return height_; }
  std::shared_ptr<server::ViewerSession> session() const { return session_; }

 private:
  int width_, height_;
  std::shared_ptr<server::ViewerSession> session_;
  std::unique_ptr<server::HttpServer> server_;
  std::string url_;
  std::thread thread_;
};

// The cell's HTML: the live page in an iframe and, for a saved notebook whose kernel has gone
// (nbconvert's HTML), the frame the scene showed when displayed, swapped in when the page does
// not answer.
std::string view_html(const PyView& view, const PyScene& scene) {
  Image still;
  {
    RenderOptions options;
    Scene frame = scene.scene();
    frame.image.width = view.width();
    frame.image.height = view.height();
    options.spp = 1;
    py::gil_scoped_release release;
    still = render(frame, options);
  }
  const std::string png = encode_png(still, "View._repr_html_");
  const std::string encoded = py::module_::import("base64")
                                  .attr("b64encode")(py::bytes(png))
                                  .attr("decode")("ascii")
                                  .cast<std::string>();
  static int views = 0;  // ids unique within the page
  const std::string id = fmt::format("intermix-view-{}", ++views);
  return fmt::format(
      R"(<div id="{0}" style="width:{1}px;height:{2}px"><iframe src="{3}" width="{1}" height="{2}" )"
      R"(style="border:0" title="intermix view"></iframe></div>)"
      R"(<script>fetch("{3}", {{mode: "no-cors"}}).catch(function () {{)"
      R"(document.getElementById("{0}").innerHTML = '<img alt="intermix view" src="data:image/png;base64,{4}">';}});</script>)",
      id, view.width(), view.height(), view.url(), encoded);
}

}  // namespace

void bind_view(py::module_& m) {
  py::class_<PyView, std::shared_ptr<PyView>>(m, "View", py::dynamic_attr(),
                                              "A scene shown by intermix's viewer in this process "
                                              "(Scene.show): in Jupyter, the page in the cell.")
      .def_property_readonly("url", &PyView::url,
                             "http://127.0.0.1:PORT/?token=TOKEN: the page, for a browser on this "
                             "machine.")
      .def_property_readonly("open", &PyView::open, "False once close() was called.")
      .def("close", &PyView::close,
           "Stops the view's server: its pages stop, and the Scene no longer follows them.")
      .def(
          "_repr_html_",
          [](const py::object& self) {
            return view_html(self.cast<const PyView&>(),
                             self.attr("_scene").cast<const PyScene&>());
          },
          "The view in a notebook cell: the page in an iframe, and the scene's frame for a saved "
          "notebook whose kernel has gone.")
      .def("__repr__", [](const PyView& v) {
        return fmt::format("<intermix.View {} ({})>", v.url(), v.open() ? "open" : "closed");
      });

  py::class_<PyScene>(m.attr("Scene"))
      .def(
          "show",
          [](const py::object& self, const py::object& width, const py::object& height) {
            const int w = static_cast<int>(int_in(width, {kShow, "width"}, 64, 4096));
            const int h = static_cast<int>(int_in(height, {kShow, "height"}, 64, 4096));
            py::object view = py::cast(std::make_shared<PyView>(self.cast<PyScene&>(), w, h));
            view.attr("_scene") = self;  // its HTML shows the scene's frame
            return view;
          },
          py::arg("width") = 640, py::arg("height") = 480,
          R"doc(Shows the scene in intermix's viewer, served by this process on 127.0.0.1 with a token of
its own, and returns an intermix.View (its `url`, `close()`). In Jupyter the view appears in
the cell, `width` x `height` pixels. The view and the scene follow each other: scene.set(...)
and the other edits reach the page, and what the page changes (the camera, transfer
functions, opacity, visibility) is in the scene the next time Python reads it. Several views
may show one scene. A saved notebook's HTML keeps the frame the scene showed when displayed.
)doc");
}

}  // namespace imx::python
