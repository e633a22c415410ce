// Values on meshes: a mesh object's "overlay" (per-vertex values from an overlay file or the mesh
// file's point data) and "color_by" (a volume sampled along the vertex normals) colour its
// vertices through a transfer function, a colour map or a label table.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "intermix/io.hpp"
#include "intermix/scene.hpp"
#include "scene/scene_parsers.hpp"

namespace imx::scene_json {

// A mesh file's mesh that shares its owner with the MeshFile it was read from, so that every
// copy of the pointer (cached by the context) still leads to the file's vertex map and point
// data: mesh_file_of gives them back, nullptr for a mesh made otherwise (a primitive, a mesh
// a program gave).
std::shared_ptr<const Mesh> share_mesh_file(MeshFile file);
const MeshFile* mesh_file_of(const std::shared_ptr<const Mesh>& mesh);

// The source mesh coloured by the mesh object's "overlay" (the reader at `overlay`): keys
// "file" (an overlay file) or "array" (a point data array of the mesh file), "index" (a GIfTI
// file's data array), "frame" (a CIFTI-2 file's map, a NIfTI or MGH per-vertex file's frame),
// "structure" (a CIFTI-2 file's surface structure, "CORTEX_LEFT"; by default the one
// `surface_file`, the mesh's file, says it is), "color" (a .label's colour), and how values
// become colours (parse_value_coloring). Cached in the context by source and overlay.
std::shared_ptr<const Mesh> apply_overlay(const JsonReader& overlay,
                                          const std::shared_ptr<const Mesh>& source,
                                          SceneContext& context,
                                          const std::filesystem::path& surface_file = {});

// Every mesh object's "color_by": {"volume": name, "depth_mm": [from, to], "reduce": "mean" |
// "max" | "min", and how values become colours (default: the volume's own transfer function)}.
// Runs once every object is parsed (`objects` in scene order, `types` every object's type);
// replaces those meshes in `scene` with coloured copies (cached in the context).
void apply_color_by(const std::vector<JsonReader>& objects, Scene& scene, SceneContext& context,
                    const std::map<std::string, std::string>& types);

}  // namespace imx::scene_json
