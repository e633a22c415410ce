// The extension module intermix._intermix; the package intermix (python/intermix) re-exports it.
#include "arguments.hpp"
#include "bindings.hpp"

PYBIND11_MODULE(_intermix, m) {
  m.doc() =
      "intermix's engine: scenes of volumes, meshes and planes rendered into numpy images "
      "(use the intermix package, which re-exports this module)";
  m.attr("__version__") = IMX_VERSION;  // CMake's project version
  imx::python::bind_errors(m);
  imx::python::bind_volume(m);
  imx::python::bind_mesh(m);
  imx::python::bind_streamlines(m);
  imx::python::bind_scene(m);
  imx::python::bind_render(m);
  imx::python::bind_image(m);
  imx::python::bind_figure(m);
  imx::python::bind_view(m);
  imx::python::bind_movie(m);
  imx::python::explain_mismatched_calls(m);  // last: it routes the functions bound above
}
