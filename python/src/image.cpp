// Images between numpy and the engine: (H, W, 4) float32 premultiplied linear RGBA; sRGB display
// bytes, PNG files, and the image metrics (compare).
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>

#include <fmt/format.h>

#include "arguments.hpp"
#include "bindings.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/metrics.hpp"

namespace imx::python {
namespace {

using FloatImage = py::array_t<float, py::array::c_style | py::array::forcecast>;

// intermix.Image, the ndarray subclass the package registers (None before it does).
py::object image_type() {
  py::module_ module = py::module_::import("intermix._intermix");
  return py::getattr(module, "_image_type", py::none());
}

// An image argument: an array, or a PNG file's path (read as intermix read_png reads it).
Image image_argument(const py::handle& value, const Argument& argument) {
  const std::string what = fmt::format("{}: {}", argument.function, argument.name);
  if (is_path_like(value) || PyBytes_Check(value.ptr())) {
    const std::filesystem::path file = python::path(value, argument);
    py::gil_scoped_release release;
    return read_png(file);
  }
  return array_to_image(value, what);
}

py::array uint8_array(std::vector<uint8_t>&& bytes, int width, int height) {
  auto* owned = new std::vector<uint8_t>(std::move(bytes));
  std::shared_ptr<const void> owner(
      owned, [](const void* p) { delete static_cast<const std::vector<uint8_t>*>(p); });
  return view_array(owned->data(), py::dtype::of<uint8_t>(), {height, width, 4}, owner, true);
}

}  // namespace

py::object image_to_array(Image&& image) {
  auto* owned = new Image(std::move(image));
  std::shared_ptr<const void> owner(owned,
                                    [](const void* p) { delete static_cast<const Image*>(p); });
  py::array array = view_array(owned->data(), py::dtype::of<float>(),
                               {owned->height(), owned->width(), 4}, owner, true);
  py::object type = image_type();
  return type.is_none() ? py::object(array) : array.attr("view")(type);
}

Image array_to_image(const py::handle& value, const std::string& what) {
  py::array given;
  try {
    given = py::module_::import("numpy").attr("asarray")(value);
  } catch (py::error_already_set& e) {
    if (e.matches(PyExc_MemoryError)) throw;
    const std::string reason = py::str(e.value()).cast<std::string>();
    throw py::type_error(fmt::format("{}: a {} is not an image: {}", what, python_type_name(value),
                                     reason.substr(0, reason.find('\n'))));
  }
  if (given.ndim() != 3 || given.shape(2) != 4 || given.shape(0) < 1 || given.shape(1) < 1)
    throw py::value_error(fmt::format(
        "{}: expected an (H, W, 4) array of premultiplied linear RGBA (an image), got shape {}",
        what, py::str(given.attr("shape")).cast<std::string>()));
  if (given.dtype().kind() != 'f')
    throw py::type_error(fmt::format(
        "{}: expected floats (premultiplied linear RGBA), got dtype {}; a display image "
        "(uint8) is not linear",
        what, py::str(given.dtype()).cast<std::string>()));
  if (given.shape(0) > std::numeric_limits<int>::max() ||
      given.shape(1) > std::numeric_limits<int>::max())
    throw py::value_error(fmt::format("{}: too large", what));
  const FloatImage a = float32_array(given, what);
  Image image(static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)));
  std::memcpy(static_cast<void*>(image.data()), a.data(), image.size() * sizeof(glm::vec4));
  // A NaN would compare as equal (PSNR inf) or show as black: an image is finite, as every
  // render is.
  size_t non_finite = 0;
  const float* values = &image.data()[0].x;
  for (size_t i = 0; i < image.size() * 4; ++i) non_finite += !std::isfinite(values[i]);
  if (non_finite > 0)
    throw py::value_error(
        fmt::format("{}: {} of the image's {} values are NaN or infinite; an "
                    "image must be finite",
                    what, non_finite, image.size() * 4));
  return image;
}

void bind_image(py::module_& m) {
  m.attr("_image_type") = py::none();
  m.def(
      "_set_image_type",
      [](py::object type) { py::module_::import("intermix._intermix").attr("_image_type") = type; },
      "Registers the ndarray subclass renders are returned as (the package's Image).");

  m.def(
      "to_uint8",
      [](const ArrayParameter& image, const FlagParameter& linear_argument) {
        const Image in = array_to_image(image, "to_uint8");
        const bool linear = flag(linear_argument, {"to_uint8", "linear"});
        std::vector<uint8_t> bytes;
        {
          py::gil_scoped_release release;
          bytes = display_rgba8(in, linear);
        }
        return uint8_array(std::move(bytes), in.width(), in.height());
      },
      py::arg("image"), py::arg("linear") = false,
      R"doc(The display image of a render, as `intermix render` writes it to PNG: an (H, W, 4) uint8 array
of straight (not premultiplied) RGBA, sRGB-encoded unless `linear`.
)doc");

  m.def(
      "write_png",
      [](const ArrayParameter& image, const PathParameter& path,
         const FlagParameter& linear_argument) {
        const Image in = array_to_image(image, "write_png");
        const std::filesystem::path file = python::path(path, {"write_png", "path"});
        const bool linear = flag(linear_argument, {"write_png", "linear"});
        py::gil_scoped_release release;
        write_png(in, file, linear);
      },
      py::arg("image"), py::arg("path"), py::arg("linear") = false,
      R"doc(Writes an (H, W, 4) premultiplied linear image as 8-bit RGBA PNG (straight alpha, sRGB unless
`linear`), atomically, as `intermix render -o` does. Raises OSError when it cannot be written.
)doc");

  m.def(
      "read_png",
      [](const PathParameter& path, const FlagParameter& linear_argument) {
        const std::filesystem::path file = python::path(path, {"read_png", "path"});
        const bool linear = flag(linear_argument, {"read_png", "linear"});
        Image image;
        {
          py::gil_scoped_release release;
          image = read_png(file, linear);
        }
        return image_to_array(std::move(image));
      },
      py::arg("path"), py::arg("linear") = false,
      R"doc(Reads an 8- or 16-bit PNG back to an (H, W, 4) premultiplied linear float32 Image (sRGB
decoded unless `linear`).
)doc");

  m.def(
      "encode_png",
      [](const ArrayParameter& image, const FlagParameter& linear_argument) {
        const Image in = array_to_image(image, "encode_png");
        const bool linear = flag(linear_argument, {"encode_png", "linear"});
        std::string png;
        {
          py::gil_scoped_release release;
          png = encode_png(in, "image", linear);
        }
        return py::bytes(png);
      },
      py::arg("image"), py::arg("linear") = false,
      "The PNG file write_png would write, as bytes (what notebooks show).");

  m.def(
      "compare",
      [](const ImageParameter& a, const ImageParameter& b) {
        const Image ia = image_argument(a, {"compare", "a"});
        const Image ib = image_argument(b, {"compare", "b"});
        ImageComparison c;
        {
          py::gil_scoped_release release;
          c = compare_images(ia, ib);
        }
        py::dict out;
        out["psnr"] = c.psnr_db;
        out["ssim"] = c.ssim;
        out["max_error"] = c.max_error;
        out["frac_over_1"] = c.frac_over_1;
        out["frac_over_4"] = c.frac_over_4;
        out["frac_over_16"] = c.frac_over_16;
        return out;
      },
      py::arg("a"), py::arg("b"),
      R"doc(Compares two images of equal size as `intermix compare` does: each an (H, W, 4) premultiplied
linear array or a PNG path. Returns a dict: psnr (dB over display RGB composited over black;
inf when equal), ssim (mean SSIM of display luminance), max_error, and frac_over_1, frac_over_4,
frac_over_16 (fractions of pixels whose largest channel error exceeds 1/255, 4/255, 16/255).
Raises ValueError when the sizes differ.
)doc");

  m.def(
      "error_heat_map",
      [](const ImageParameter& a, const ImageParameter& b, const RealParameter& scale_argument) {
        const Image ia = image_argument(a, {"error_heat_map", "a"});
        const Image ib = image_argument(b, {"error_heat_map", "b"});
        const double scale = finite_real(scale_argument, {"error_heat_map", "scale"});
        if (scale <= 0.0)
          throw py::value_error(fmt::format("error_heat_map: scale {:g} is not above 0", scale));
        Image map;
        {
          py::gil_scoped_release release;
          map = error_heat_map(ia, ib, scale);
        }
        return image_to_array(std::move(map));
      },
      py::arg("a"), py::arg("b"), py::arg("scale") = 16.0,
      "The per-pixel error as a heat map Image (black: equal; an error of 1/scale is full "
      "heat), as `intermix compare --heat-map` writes it.");
}

}  // namespace imx::python
