// Scene documents from Python values and back: dicts, lists, strings, numbers, booleans, None,
// numpy arrays and scalars, paths, and intermix.Volume / Mesh / Streamlines objects, which the
// document names by placeholders ({"$volume": id}, {"$mesh": id}, {"$streamlines": id}) that the
// scene loader resolves through SceneContext::given_volumes / given_meshes / given_streamlines.
#pragma once
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "bindings.hpp"

namespace imx::python {

// The Volume, Mesh and Streamlines objects a document names, by id.
using GivenSources = std::map<std::string, py::object>;

// `value` as JSON; Volume and Mesh objects are added to `sources`. Throws ValueError
// "origin: path: ..." for a value JSON cannot hold (a non-finite float, a key that is not a
// string, an unknown type, nesting deeper than the scene loader allows).
nlohmann::json to_document(const py::handle& value, GivenSources& sources,
                           const std::string& origin, const std::string& path = {});

// The document as Python values, with the placeholders replaced by their Volume and Mesh objects.
py::object from_document(const nlohmann::json& document, const GivenSources& sources);

// Removes from `sources` every id that `document` does not name.
void keep_named_sources(const nlohmann::json& document, GivenSources& sources);

}  // namespace imx::python
