// The Python package's C++ side (_intermix): one bind_* per concept, and the types they share.
#pragma once
#include <map>
#include <memory>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "intermix/image.hpp"
#include "intermix/mesh.hpp"
#include "intermix/streamlines.hpp"
#include "intermix/volume.hpp"

namespace imx::python {

namespace py = pybind11;

void bind_errors(py::module_& m);
void bind_volume(py::module_& m);
void bind_mesh(py::module_& m);
void bind_streamlines(py::module_& m);
void bind_scene(py::module_& m);
void bind_render(py::module_& m);
void bind_image(py::module_& m);
void bind_figure(py::module_& m);  // after bind_scene: a method of Scene
void bind_view(py::module_& m);    // after bind_scene: Scene.show
void bind_movie(py::module_& m);

// An exception whose message goes to Python as RuntimeError: a render that failed.
class RenderFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// intermix.Volume: voxels the engine reads and the numpy array holding them, kept alive.
struct PyVolume {
  std::string id;  // "volume-7": how a scene document names it ({"$volume": id})
  std::shared_ptr<const VolumeData> data;
  py::array array;             // the array as the engine reads it: C order, indexed [k, j, i]
  py::object given;            // the array as it was given
  bool shares_memory = false;  // the engine reads the given array's own memory
  bool lps = true;             // the affine was given in LPS (else RAS)
};

// intermix.Mesh: a triangle mesh in LPS millimetres.
struct PyMesh {
  std::string id;  // "mesh-3": how a scene document names it ({"$mesh": id})
  std::shared_ptr<const Mesh> mesh;
};

// intermix.Streamlines: a tractogram in LPS millimetres, from a file or from arrays.
struct PyStreamlines {
  std::string id;  // "streamlines-4": how a scene document names it ({"$streamlines": id})
  std::shared_ptr<const Streamlines> data;
  std::vector<std::string> notes;  // what reading chose (streamlines dropped, a field missing)
};

// A fresh id for a volume, mesh or streamlines ("volume-1", "mesh-2", ...).
std::string next_source_id(const char* kind);

// A numpy array viewing `count` elements of T at `data` with `shape`, C order, which keeps
// `owner` alive; read-only unless `writeable`.
py::array view_array(const void* data, const py::dtype& dtype, std::vector<py::ssize_t> shape,
                     std::shared_ptr<const void> owner, bool writeable);

// An image as an (H, W, 4) float32 numpy array of premultiplied linear RGBA (no copy: the
// array owns the image's pixels), as intermix.Image when the package registered that type.
py::object image_to_array(Image&& image);
// An (H, W, 4) array (or anything numpy turns into one) as an image; `what` names it in errors.
Image array_to_image(const py::handle& array, const std::string& what);

}  // namespace imx::python
