// intermix.Mesh (numpy vertices and triangles) and read_mesh.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>
#include <pybind11/stl.h>

#include "arguments.hpp"
#include "bindings.hpp"
#include "core/colour.hpp"
#include "core/limits.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/mesh/mesh_space.hpp"
#include "io/mesh/vertex_normals.hpp"

namespace imx::python {
namespace {

using FloatRows = py::array_t<float, py::array::c_style | py::array::forcecast>;

// An (n, 3) array of floats (n given, or any n >= 1 when `n` is -1), copied into vec3s.
std::vector<glm::vec3> vec3_rows(const py::handle& value, const char* name, py::ssize_t n) {
  py::array given = array_argument(value, {"Mesh", name}, "an (N, 3) array of numbers");
  if (given.ndim() != 2 || given.shape(1) != 3 || (n >= 0 && given.shape(0) != n))
    throw py::value_error(fmt::format("Mesh: {} must have shape ({}, 3), got {}", name,
                                      n >= 0 ? std::to_string(n) : "N",
                                      py::str(given.attr("shape")).cast<std::string>()));
  const char kind = given.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(fmt::format("Mesh: {} must be numbers, got dtype {}", name,
                                     py::str(given.dtype()).cast<std::string>()));
  const FloatRows a = float32_array(given, fmt::format("Mesh: {}", name));
  std::vector<glm::vec3> out(static_cast<size_t>(a.shape(0)));
  if (!out.empty()) std::copy_n(a.data(), out.size() * 3, &out[0].x);
  return out;
}

// The largest crease angle: 180 degrees splits no edge.
constexpr double kMaxCreaseAngleDeg = 180.0;

std::shared_ptr<PyMesh> make_mesh(const ArrayParameter& vertices, const ArrayParameter& triangles,
                                  const OptionalArrayParameter& normals,
                                  const OptionalArrayParameter& colors,
                                  const TextParameter& space_argument,
                                  const RealParameter& crease_argument) {
  const std::string space = text(space_argument, {"Mesh", "space"});
  const double crease_angle_deg =
      real_in(crease_argument, {"Mesh", "crease_angle_deg"}, 0.0, kMaxCreaseAngleDeg);
  const bool ras = space == "RAS" || space == "ras";
  if (!ras && space != "LPS" && space != "lps")
    throw py::value_error(fmt::format("Mesh: space '{}' is not LPS or RAS", space));
  Mesh mesh;
  mesh.positions = vec3_rows(vertices, "vertices", -1);
  const auto n = static_cast<py::ssize_t>(mesh.positions.size());
  if (n == 0) throw py::value_error("Mesh: no vertices");
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3& p = mesh.positions[i];
    if (!(std::abs(p.x) <= kMaxCoordinateMm && std::abs(p.y) <= kMaxCoordinateMm &&
          std::abs(p.z) <= kMaxCoordinateMm))
      throw py::value_error(
          fmt::format("Mesh: vertex {} at ({:g}, {:g}, {:g}) is not a finite position within "
                      "{:g} mm of the origin",
                      i, p.x, p.y, p.z, kMaxCoordinateMm));
  }

  py::array t =
      array_argument(triangles, {"Mesh", "triangles"}, "an (M, 3) array of vertex indices");
  if (t.ndim() != 2 || t.shape(1) != 3 || t.shape(0) == 0)
    throw py::value_error(fmt::format("Mesh: triangles must have shape (M, 3) with M >= 1, got {}",
                                      py::str(t.attr("shape")).cast<std::string>()));
  if (t.dtype().kind() != 'i' && t.dtype().kind() != 'u')
    throw py::type_error(fmt::format("Mesh: triangles must be integer vertex indices, got dtype {}",
                                     py::str(t.dtype()).cast<std::string>()));
  auto indices = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(t);
  if (!indices)  // uint64 beyond int64
    throw py::value_error("Mesh: triangles hold indices beyond the vertices");
  mesh.triangles.resize(static_cast<size_t>(indices.shape(0)));
  const int64_t* idx = indices.data();
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int64_t v = idx[f * 3 + static_cast<size_t>(c)];
      if (v < 0 || v >= n)
        throw py::value_error(
            fmt::format("Mesh: triangle {} uses vertex {}, but there are {} vertices", f, v, n));
      mesh.triangles[f][c] = static_cast<unsigned>(v);
    }
  }
  if (!colors.is_none()) {
    mesh.colors = vec3_rows(colors, "colors", n);
    for (size_t i = 0; i < mesh.colors.size(); ++i)
      for (int c = 0; c < 3; ++c)
        if (!(mesh.colors[i][c] >= 0.0f && mesh.colors[i][c] <= 1.0f))
          throw py::value_error(
              fmt::format("Mesh: colors[{}] = ({:g}, {:g}, {:g}) is not RGB in [0, 1]", i,
                          mesh.colors[i].x, mesh.colors[i].y, mesh.colors[i].z));
    // Display colours, as a mesh file's: decoded once here (core/colour.hpp).
    for (glm::vec3& c : mesh.colors) c = display_to_linear(c);
  }
  if (!normals.is_none()) {
    mesh.normals = vec3_rows(normals, "normals", n);
    for (size_t i = 0; i < mesh.normals.size(); ++i)
      if (!std::isfinite(mesh.normals[i].x + mesh.normals[i].y + mesh.normals[i].z))
        throw py::value_error(fmt::format("Mesh: normals[{}] is not finite", i));
  }
  if (ras) detail::flip_ras_lps(mesh);
  if (mesh.normals.empty()) detail::compute_vertex_normals(mesh, crease_angle_deg);
  auto out = std::make_shared<PyMesh>();
  out->id = next_source_id("mesh");
  out->mesh = std::make_shared<const Mesh>(std::move(mesh));
  return out;
}

// An (n, 3) read-only view of vec3 data owned by the mesh.
py::array rows_view(const std::shared_ptr<const Mesh>& mesh, const void* data, size_t n,
                    const char* dtype) {
  return view_array(data, py::dtype(dtype), {static_cast<py::ssize_t>(n), 3}, mesh, false);
}

}  // namespace

void bind_mesh(py::module_& m) {
  py::class_<PyMesh, std::shared_ptr<PyMesh>>(
      m, "Mesh",
      R"doc(A triangle mesh in world millimetres, usable as a mesh object's "source" in a scene (placed
further by the object's "transform").

Mesh(vertices, triangles, normals=None, colors=None, *, space="LPS", crease_angle_deg=60)

vertices: (N, 3) floats; triangles: (M, 3) integer vertex indices, counter-clockwise seen from
outside; normals: (N, 3) per-vertex normals (shading only), or None to compute them as for mesh
files (angle-weighted, vertices split at edges sharper than crease_angle_deg, which may change
the vertex count); colors: (N, 3) display (sRGB) RGB in [0, 1] per vertex, as mesh files and
scene files give colours, scaling the material colour.
space: "LPS" or "RAS" (x and y negated into LPS). The arrays are copied (float32, uint32).
Raises ValueError for bad shapes, indices or non-finite values.
)doc")
      .def(py::init(&make_mesh), py::arg("vertices"), py::arg("triangles"),
           py::arg("normals") = py::none(), py::arg("colors") = py::none(), py::kw_only(),
           py::arg("space") = "LPS", py::arg("crease_angle_deg") = 60.0)
      .def_property_readonly(
          "vertices",
          [](const PyMesh& p) {
            return rows_view(p.mesh, p.mesh->positions.data(), p.mesh->positions.size(), "float32");
          },
          "(N, 3) float32 vertex positions, LPS mm (read-only).")
      .def_property_readonly(
          "triangles",
          [](const PyMesh& p) {
            return rows_view(p.mesh, p.mesh->triangles.data(), p.mesh->triangles.size(), "uint32");
          },
          "(M, 3) uint32 vertex indices (read-only).")
      .def_property_readonly(
          "normals",
          [](const PyMesh& p) -> py::object {
            if (p.mesh->normals.empty()) return py::none();
            return rows_view(p.mesh, p.mesh->normals.data(), p.mesh->normals.size(), "float32");
          },
          "(N, 3) float32 unit normals, or None.")
      .def_property_readonly(
          "colors",
          [](const PyMesh& p) -> py::object {
            if (p.mesh->colors.empty()) return py::none();
            // A copy in display colours, as they were given (the mesh holds them linear).
            py::array_t<float> out(
                {static_cast<py::ssize_t>(p.mesh->colors.size()), py::ssize_t{3}});
            auto rows = out.mutable_unchecked<2>();
            for (size_t i = 0; i < p.mesh->colors.size(); ++i) {
              const glm::vec3 c = linear_to_display(p.mesh->colors[i]);
              for (int k = 0; k < 3; ++k) rows(static_cast<py::ssize_t>(i), k) = c[k];
            }
            out.attr("flags").attr("writeable") = false;
            return out;
          },
          "(N, 3) float32 display (sRGB) RGB per vertex, as given, or None (read-only copy).")
      .def("__repr__", [](const PyMesh& p) {
        return fmt::format("<intermix.Mesh {} vertices, {} triangles{}{}>",
                           p.mesh->positions.size(), p.mesh->triangles.size(),
                           p.mesh->normals.empty() ? "" : ", normals",
                           p.mesh->colors.empty() ? "" : ", colors");
      });

  m.def(
      "read_mesh",
      [](const PathParameter& path, const OptionalTextParameter& space_argument,
         const RealParameter& crease_argument) {
        const std::filesystem::path file = python::path(path, {"read_mesh", "path"});
        const std::optional<std::string> space =
            optional_text(space_argument, {"read_mesh", "space"});
        const double crease_angle_deg =
            real_in(crease_argument, {"read_mesh", "crease_angle_deg"}, 0.0, kMaxCreaseAngleDeg);
        MeshReadOptions options;
        if (space) {
          if (*space != "LPS" && *space != "RAS")
            throw py::value_error(fmt::format("read_mesh: space '{}' is not LPS or RAS", *space));
          options.space = *space == "RAS" ? MeshSpace::ras : MeshSpace::lps;
        }
        options.crease_angle_deg = crease_angle_deg;
        MeshFile read;
        {
          py::gil_scoped_release release;
          read = read_mesh_file(file, options);
        }
        auto out = std::make_shared<PyMesh>();
        out->id = next_source_id("mesh");
        out->mesh = std::make_shared<const Mesh>(std::move(read.mesh));
        return out;
      },
      py::arg("path"), py::kw_only(), py::arg("space") = py::none(),
      py::arg("crease_angle_deg") = 60.0,
      R"doc(Reads a triangle mesh: PLY, OBJ, STL, OFF, glTF (.gltf, .glb), GIfTI (.gii), in LPS mm.
The file's space is `space` ("LPS" or "RAS") when given, else what its header says (3D Slicer's
SPACE=RAS), else the format's own (GIfTI: RAS), else LPS. Normals come from the file, else are
computed (split at crease_angle_deg). Returns a Mesh (.vertices, .triangles, .normals, .colors).
Raises OSError when the file cannot be read, ValueError when its content is wrong.
)doc");
}

}  // namespace imx::python
