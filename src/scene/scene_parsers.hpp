// The parsers for each part of a scene file, shared by load_scene and its tests.
#pragma once
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>

#include "intermix/io.hpp"
#include "intermix/scene.hpp"
#include "scene/annotation.hpp"
#include "scene/camera_framing.hpp"
#include "scene/json_reader.hpp"
#include "scene/mesh_space_evidence.hpp"

namespace imx::scene_json {

// State shared while one scene's objects are read: where relative paths start, and loaded
// sources so that objects with the same source share one copy. A program that parses edited
// documents of one scene again (the Python package) keeps its context, so that unchanged
// sources are neither read again nor change identity (imx::Renderer recognises data by it).
struct SceneContext {
  std::filesystem::path base_dir;
  std::map<std::string, std::shared_ptr<const VolumeData>> volumes;
  std::map<std::string, std::shared_ptr<const Mesh>> meshes;
  std::vector<std::string> notes;                  // moved into Scene::notes when loading ends
  std::map<std::string, glm::dvec2> windows = {};  // DICOM series' own windows, by volume key
  std::map<std::string, int> frame_counts = {};    // frames of multi-frame sources, by key
  // DICOM series' modality and units ("CT", "HU"), by volume key: what the automatic transfer
  // function goes by.
  std::map<std::string, std::pair<std::string, std::string>> modalities = {};
  // The transfer function (and shading) chosen for each volume object that named none, by its
  // JSON path ("objects[2]"): what a saved document writes in its place.
  std::map<std::string, std::pair<nlohmann::json, nlohmann::json>> automatic_looks = {};
  // Volumes and meshes a program gives instead of files (the Python package's numpy arrays):
  // a source {"$volume": ID} or {"$mesh": ID} names one. Files have none, so there the key is
  // unknown like any other.
  std::map<std::string, std::shared_ptr<const VolumeData>> given_volumes = {};
  std::map<std::string, std::shared_ptr<const Mesh>> given_meshes = {};
  std::map<std::string, std::shared_ptr<const Streamlines>> given_streamlines = {};  // $streamlines
  // Meshes placed by an object's transform, by source and transform, and the keys of `volumes`,
  // `meshes` and `placed_meshes` the last document used (a program drops the others).
  std::map<std::string, std::shared_ptr<const Mesh>> placed_meshes = {};
  // Tractograms by file and value files, and placed by a transform with their tubes' cache.
  std::map<std::string, std::shared_ptr<const Streamlines>> streamlines = {};
  std::map<std::string, std::pair<std::shared_ptr<const Streamlines>, std::shared_ptr<TubeCache>>>
      placed_streamlines = {};
  std::set<std::string> used = {};
  // Set: each volume object's data is only the box this chooses (load_scene by region).
  VolumeRegionChooser region = {};
  // The scene's "space": points, directions and inline transforms it gives are RAS when ras
  // (world_space.hpp turns them into LPS); also the space of mesh files that say none.
  MeshSpace world_space = MeshSpace::lps;
  // Mesh objects whose file's space the document did not give: checked against the volumes
  // once every object is read (mesh_space_evidence.hpp).
  std::vector<MeshSpaceCandidate> mesh_space_candidates = {};
  // The rows of the scene's image: what an OME-Zarr source at "level": "view" is read for.
  int image_rows = 512;
  // The last document's "annotations" (parse_scene_document), which SceneDocument keeps.
  std::vector<Annotation> annotations = {};

  // A "file" value resolved against base_dir; throws naming the resolved path when missing.
  std::filesystem::path resolve_file(const JsonReader& file) const;
};

// A scene file's text: throws imx::FileError naming the file when it cannot be read.
std::string read_scene_file(const std::filesystem::path& file);
// JSON text parsed as a scene document (strictly: no key twice), an object at the top level;
// throws imx::Error "origin: invalid JSON: ..." otherwise.
nlohmann::json parse_scene_json(const std::string& json_text, const std::string& origin);
// The whole scene from its JSON document (after --set overrides), reading sources through
// `context` (load_scene and parse_scene use a fresh one). `origin` names the document in errors.
Scene parse_scene_document(const nlohmann::json& root, const std::string& origin,
                           SceneContext& context);

// A "view" (anterior, left, ...) sets *framed_view and leaves eye, target and up to framing: the
// caller frames the objects (camera_framing.hpp); without `framed_view`, "view" is an error.
// `space`: the scene's; eye, target and up given in RAS are read into LPS.
Camera parse_camera(const JsonReader& r, std::optional<PatientView>* framed_view = nullptr,
                    MeshSpace space = MeshSpace::lps);
ImageSettings parse_image(const JsonReader& r);
std::vector<Light> parse_lights(const JsonReader& r, MeshSpace space = MeshSpace::lps);
RenderSettings parse_render(const JsonReader& r);
// The index in `scene.volumes` of the volume called `name`, else one error at `at` saying what
// `name` is instead (a mesh, a plane: `object_types` maps names to types) or the nearest name.
int find_volume(const JsonReader& at, const std::string& name, const Scene& scene,
                const std::map<std::string, std::string>& object_types);
// Throws unless render.last_volume (when set) names one of `scene`'s volumes; `object_types`
// maps every object's name to its type, for a clear message when it names a mesh or a plane.
void check_last_volume(const JsonReader& render, const Scene& scene,
                       const std::map<std::string, std::string>& object_types);
// Throws unless every name in render.mixing_priority is one of `scene`'s volumes, listed once.
void check_mixing_priority(const JsonReader& render, const Scene& scene,
                           const std::map<std::string, std::string>& object_types);

// The "csg" block over `scene`'s parsed objects; nullopt for "csg": null. Throws for a name
// that is not a dvr volume or a closed mesh, conflicting presences, too many primitives or
// too deep a nesting. Meshes it names that face inward are flipped in `scene`.
std::optional<CsgExpression> parse_csg(const JsonReader& r, Scene& scene);
// Every volume's "clip" list: names of closed meshes and what to keep of them, into
// VolumeObject::clip_meshes. Throws for a name that is not a closed mesh, a keep that is not
// inside or outside, a mesh named twice in one list, or more than 64 clip meshes. Meshes that
// face inward are flipped in `scene`. `objects` are the readers of the scene's objects, in
// scene.order's order.
void parse_clip_meshes(const std::vector<JsonReader>& objects, Scene& scene);
// Throws at objects[i].interior for a mesh with an interior that is not a primitive of
// scene.csg; `objects` are the readers of the scene's objects, in scene.order's order.
void check_interiors(const std::vector<JsonReader>& objects, const Scene& scene);

// {"matrix": 4x4 row-major} or {"translate", "rotate_deg", "scale"} as T * Rz * Ry * Rx * S
// (in context.world_space), or {"file", "invert", "moving", "reference"}: a registration file's
// placement of its moving image (registration/transform_file.hpp), inverted by "invert".
// Throws when an entry is not finite or the transform is singular or not affine.
glm::dmat4 parse_transform(const JsonReader& r, SceneContext& context);
// The displacement field (registration/displacement_field.hpp) a volume's "transform": {"file"}
// names, resolved; nullopt for any other transform.
std::optional<std::filesystem::path> displacement_field_of(const JsonReader& r,
                                                           SceneContext& context);
// `moving` resampled through `field` once (cached per source and field), with a note giving the
// time; `file` is the transform's "file" value, for errors.
std::shared_ptr<const VolumeData> warped_volume(const JsonReader& file,
                                                std::shared_ptr<const VolumeData> moving,
                                                const std::filesystem::path& field,
                                                SceneContext& context);

// {"enabled", "ambient", "diffuse", "specular", "shininess"}; `enabled` defaults to true.
Shading parse_shading(const JsonReader& r);
// A positive number of mm, or "auto" (nullopt).
std::optional<double> parse_thickness(const JsonReader& r);
// An object's "visible" (default true). An invisible object draws nothing but is still data (a
// plane's volume, a clip mesh, a CSG primitive): its parser zeroes what it would show.
bool parse_visible(const JsonReader& object);

// A transfer function and, for a preset or a Slicer file, the shading it comes with (used when
// the volume gives none).
struct ParsedTransferFunction {
  TransferFunction transfer_function;
  std::optional<Shading> shading;
};
// {"points": [[value, r, g, b, a], ...]}, {"preset": "ct-bone"} (3D Slicer's presets; Slicer's
// names work too) or {"file": "x.vp" | "x.json", "name": map in a ParaView file}; "shift" and
// "scale" move the points (presets/tf_adjust.hpp), "unit_distance" sets the alphas' mm.
ParsedTransferFunction parse_transfer_function(const JsonReader& r, SceneContext& context);
// A colour map's name (presets/colormap.hpp); the error lists them all.
Colormap parse_colormap(const JsonReader& v);

// A thick slab {"thickness": mm in [0, kMaxSlabThicknessMm], "mode": "mip" (the default),
// "minip" or "mean"}: a plane's "slab"; slab_json writes one back.
constexpr double kMaxSlabThicknessMm = 1000.0;
SlabProjection parse_slab(const JsonReader& r);
nlohmann::json slab_json(const SlabProjection& s);
// A volume's "slabs": {"axial", "coronal", "sagittal": a slab each, all optional}, its 2-D
// reading views' thick slabs.
std::array<SlabProjection, 3> parse_reading_slabs(const JsonReader& r);
// The views' slabs thicker than 0 as "slabs" gives them ({} when none).
nlohmann::json reading_slabs_json(const std::array<SlabProjection, 3>& slabs);

// A window: [centre, width] (width > 0) or the name of one of 3D Slicer's window/level presets
// ("ct-brain"), for planes and a volume's 2-D views.
glm::dvec2 parse_window(const JsonReader& v);

// A volume's "clip_planes": [{"point": [3], "normal": [3]}, ...], normals normalized.
std::vector<ClipPlane> parse_clip_planes(const JsonReader& r, MeshSpace space = MeshSpace::lps);
VolumeObject parse_volume_object(const JsonReader& r, SceneContext& context);
MeshObject parse_mesh_object(const JsonReader& r, SceneContext& context);
// {"source": {"file", "values"}, "radius", "color_by", "color", "value", "colormap", "range",
// "opacity", "group_opacity", "shading", "stride", "min_length", "regions", "thickness",
// "clip_planes" (as a volume's; cut tubes are capped)}.
StreamlineObject parse_streamline_object(const JsonReader& r, SceneContext& context);
// A "connectome" object, drawn as a streamline object of spheres and tubes: {"source": {"file",
// "edges"}, "node_scale", "edge_scale", "node_min", "node_max", "edge_min", "edge_max",
// "node_colormap", "edge_colormap" (and their "_negative"), "opacity", "shading", "transform"}.
StreamlineObject parse_connectome_object(const JsonReader& r, SceneContext& context);
// `scene` holds the volumes, which "volume" may name; `object_types` maps every object's name
// to its type, for a clear message when "volume" names a mesh or a plane.
PlaneObject parse_plane_object(const JsonReader& r, const Scene& scene,
                               const std::map<std::string, std::string>& object_types,
                               MeshSpace space = MeshSpace::lps);

// The top-level "annotations": [{"kind": "ruler"|"angle"|"ellipse"|"polygon", "points": [[x, y,
// z], ...], "volume" (ROIs: a volume's name), "label"}, ...] (docs/viewer.md), points read into
// LPS from `space`. Throws naming the path for an unknown kind or key, a wrong number of points,
// a non-finite or far point, degenerate geometry (an arm or axis of length 0, a polygon of no
// area or not flat), more than kMaxAnnotations, or a volume `scene` lacks.
std::vector<Annotation> parse_annotations(const JsonReader& r, const Scene& scene,
                                          const std::map<std::string, std::string>& object_types,
                                          MeshSpace space = MeshSpace::lps);

}  // namespace imx::scene_json
