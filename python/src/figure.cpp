// Scene.figure: the figures of `intermix figure` (src/figure/figure.hpp) from Python.
#include <fmt/format.h>

#include "arguments.hpp"
#include "bindings.hpp"
#include "figure/figure.hpp"
#include "figure/figure_extent.hpp"
#include "scene.hpp"

namespace imx::python {
namespace {

constexpr std::string_view kFunction = "Scene.figure";

glm::dvec3 point_argument(const py::handle& value, std::string_view name) {
  const py::array a = array_argument(value, {kFunction, name}, "3 numbers", py::dtype("float64"));
  if (a.ndim() != 1 || a.shape(0) != 3)
    throw py::value_error(fmt::format("{}: {} must be 3 numbers (x, y, z)", kFunction, name));
  const double* p = static_cast<const double*>(a.data());
  return {p[0], p[1], p[2]};
}

}  // namespace

void bind_figure(py::module_& m) {
  m.def(
      "_anatomy_box",
      [](const py::object& volume) {
        const PyVolume& v =
            instance_of<PyVolume>(volume, {"_anatomy_box", "volume"}, "an intermix.Volume");
        VolumeObject object;
        object.data = v.data;
        object.index_to_world = v.data->index_to_world;
        const WorldBox box = anatomy_box(object);
        return py::make_tuple(py::make_tuple(box.lo.x, box.lo.y, box.lo.z),
                              py::make_tuple(box.hi.x, box.hi.y, box.hi.z));
      },
      "The LPS box (lo, hi) of the volume's voxels above its background: what figures frame.");
  py::class_<PyScene>(m.attr("Scene"))
      .def(
          "figure",
          [](const PyScene& s, const py::object& kind, const py::object& cut,
             const py::object& axis, const py::object& cuts, const py::object& slices,
             const py::object& columns, const py::object& height, const py::object& colorbar,
             const py::object& annotate, const py::object& crosshair, const py::object& plot_abs) {
            FigureOptions o;
            const std::string kind_name = text(kind, {kFunction, "kind"});
            const std::optional<FigureKind> k = find_figure_kind(kind_name);
            if (!k)
              throw py::value_error(fmt::format("{}: kind '{}' is not one of ortho, mosaic, glass",
                                                kFunction, kind_name));
            o.kind = *k;
            if (!cut.is_none()) o.cut = point_argument(cut, "cut");
            const std::string axis_name = text(axis, {kFunction, "axis"});
            const std::optional<SliceAxis> a = find_slice_axis(axis_name);
            if (!a)
              throw py::value_error(fmt::format(
                  "{}: axis '{}' is not one of axial, coronal, sagittal", kFunction, axis_name));
            o.axis = *a;
            if (!cuts.is_none()) {
              const py::array c =
                  array_argument(cuts, {kFunction, "cuts"}, "numbers", py::dtype("float64"));
              if (c.ndim() != 1 || c.shape(0) < 1 || c.shape(0) > 64)
                throw py::value_error(fmt::format("{}: cuts must be 1 to 64 numbers", kFunction));
              for (py::ssize_t i = 0; i < c.shape(0); ++i)
                o.cuts.push_back(static_cast<const double*>(c.data())[i]);
            }
            o.slices = static_cast<int>(int_in(slices, {kFunction, "slices"}, 1, 64));
            o.columns = static_cast<int>(int_in(columns, {kFunction, "columns"}, 0, 64));
            o.panel_height = static_cast<int>(int_in(height, {kFunction, "height"}, 16, 4096));
            o.colorbar = flag(colorbar, {kFunction, "colorbar"});
            o.annotate = flag(annotate, {kFunction, "annotate"});
            o.crosshair = flag(crosshair, {kFunction, "crosshair"});
            o.plot_abs = flag(plot_abs, {kFunction, "plot_abs"});
            Figure figure;
            {
              py::gil_scoped_release release;
              figure = render_figure(s.scene(), o);
            }
            return image_to_array(std::move(figure.image));
          },
          py::arg("kind") = "ortho", py::arg("cut") = py::none(), py::arg("axis") = "axial",
          py::arg("cuts") = py::none(), py::arg("slices") = 7, py::arg("columns") = 0,
          py::arg("height") = 256, py::arg("colorbar") = true, py::arg("annotate") = true,
          py::arg("crosshair") = true, py::arg("plot_abs") = true,
          R"doc(A figure for a paper from the scene's volumes, as `intermix figure` draws it: "ortho" (three
cuts through `cut`), "mosaic" (`slices` cuts along `axis`, or at `cuts`) or "glass" (three
projections of the map over the anatomy's outline). The first volume is the anatomy, in grey
through its reading window; the others are overlays in their transfer functions' colours,
opaque where they show (a glass brain: one map, over the first volume's outline when there
are two). `cut` (x, y, z) and `cuts` are in the scene's world (LPS mm); the defaults are the
first overlay's peak and cuts spread over where it shows. `height`: pixels of the tallest
panel. Orientation letters and cut coordinates (RAS, "x=12") unless annotate=False, the
overlays' colour bars beside the panels unless colorbar=False. Returns an intermix.Image.
)doc");
}

}  // namespace imx::python
