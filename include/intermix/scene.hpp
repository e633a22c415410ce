// Scene: camera, image, lights, volumes, meshes, planes and render settings of one frame.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "intermix/labels.hpp"
#include "intermix/mesh.hpp"
#include "intermix/streamlines.hpp"
#include "intermix/volume.hpp"

namespace imx {

enum class Projection { perspective, orthographic };

struct Camera {
  glm::dvec3 eye{0.0, -600.0, 0.0};
  glm::dvec3 target{0.0};
  glm::dvec3 up{0.0, 0.0, 1.0};
  double fov_deg = 30.0;        // vertical field of view (perspective)
  double ortho_height = 200.0;  // visible height in mm (orthographic)
  Projection projection = Projection::perspective;
};

struct ImageSettings {
  int width = 512;
  int height = 512;
  glm::vec4 background{0.0f, 0.0f, 0.0f, 1.0f};  // straight (not premultiplied) RGBA
};

enum class LightType { headlight, directional };

struct Light {
  LightType type = LightType::headlight;
  glm::dvec3 direction{0.0, 0.0, -1.0};  // directional: the way the light travels, world space
  float intensity = 1.0f;
  glm::vec3 color{1.0f};
};

// Blinn-Phong coefficients: emissive + ambient + diffuse (N.L) + specular (N.H)^shininess.
struct Shading {
  bool enabled = false;
  float ambient = 0.2f;
  float diffuse = 0.7f;
  float specular = 0.3f;
  float shininess = 32.0f;
};

struct TfPoint {
  double value = 0.0;
  glm::vec4 rgba{0.0f};  // straight colour; alpha is the opacity of unit_distance mm of material
};

// Piecewise-linear RGBA over data values; constant beyond the first and last points.
struct TransferFunction {
  std::vector<TfPoint> points;
  double unit_distance = 1.0;  // mm of material the alphas refer to (SPEC §2, dt0)
};

// dvr: emission-absorption; iso: the first crossing of iso_value; mip / minip: the TF at the
// largest / smallest value along the ray; xray: a radiograph of the TF's attenuation (SPEC §2).
enum class VolumeStyle { dvr, iso, mip, minip, xray };

// What xray shows: the line integral of the attenuation (1 - exp(-sum mu dt), thickness shows),
// or the TF at the mean value along the ray.
enum class XrayMode { integral, average };

// Keeps the half-space where dot(p - point, normal) >= 0.
struct ClipPlane {
  glm::dvec3 point{0.0};
  glm::dvec3 normal{0.0, 0.0, 1.0};
};

// A closed mesh restricting a volume (SPEC §7 clip geometry): the volume is sampled only inside
// it (probing) or only outside it (cutting). The mesh itself is drawn with its own material, or
// not at all when the material's opacity is 0.
struct ClipMesh {
  int mesh = -1;             // index into Scene::meshes; closed and facing outward
  bool keep_inside = false;  // true: probing, false: cutting
};

// A thick slab's projection (2-D reading views, MPR planes): each pixel the max (MIP), min
// (MinIP) or mean of the volume's samples along the plane's normal across `thickness` mm centred
// on the plane; a thickness of 0 is the plane alone.
enum class SlabMode : uint8_t { mip, minip, mean };
struct SlabProjection {
  double thickness = 0.0;  // mm
  SlabMode mode = SlabMode::mip;
  bool operator==(const SlabProjection&) const = default;
};

struct VolumeObject {
  std::string name;
  std::shared_ptr<const VolumeData> data;
  glm::dmat4 index_to_world{1.0};  // the object's transform applied to data->index_to_world
  TransferFunction transfer_function;
  VolumeStyle style = VolumeStyle::dvr;
  double iso_value = 0.0;
  XrayMode xray_mode = XrayMode::integral;
  Shading shading;
  std::vector<ClipPlane> clip_planes;
  std::vector<ClipMesh> clip_meshes;         // a sample shows only where every one of them keeps it
  std::optional<glm::dvec2> display_window;  // the source's own centre and width (DICOM tags)
  // The scene file's "window" (centre, width): the 2-D reading views' window as the user set it;
  // without it they follow the initial-window rule (volume/display_window.hpp).
  std::optional<glm::dvec2> window;
  // The scene file's "slabs": the axial, coronal and sagittal reading views' thick slabs.
  std::array<SlabProjection, 3> reading_slabs{};
  std::string units;  // of the values, as the source says ("HU", "BQML", "g/ml"); "" if unknown
  // Where `data` lies in its source: all of it, unless the scene was loaded by region
  // (SceneLoadOptions::region), when data holds only `region` of a grid of `source_dims`.
  glm::ivec3 source_dims{0};
  VoxelBox region;
  // Of a multi-frame (4-D) source (fMRI, DWI, ...): which frame `data` holds, of how many.
  int frame = 0, frames = 1;
  // Style "labels" (a dvr volume whose voxels are labels): the colour table and classification
  // (volume/label_classifier.hpp); null for every other volume. The TF is then unused.
  std::shared_ptr<const LabelMap> labels;
};

struct Material {
  glm::vec3 color{1.0f};
  float opacity = 1.0f;
  Shading shading{true};
};

// A homogeneous medium filling a closed mesh that is a CSG primitive (SPEC §8).
struct MeshInterior {
  glm::vec3 color{1.0f};
  float opacity = 0.0f;        // of unit_distance mm of the medium
  double unit_distance = 1.0;  // mm
};

struct MeshObject {
  std::string name;
  std::shared_ptr<const Mesh> mesh;  // world space: the object's transform is already applied
  Material material;
  std::optional<double> thickness;       // mm; empty means "auto" (SPEC §4 / §6 defaults)
  std::optional<MeshInterior> interior;  // only on CSG primitives
};

// A colour map: a value in [0, 1] to colour (src/presets/colormap.hpp names them and says where
// each comes from). cold_hot is signed: its lower half is the cold side, its upper the hot one.
enum class Colormap : uint8_t {
  grey,
  hot,
  inferno,
  viridis,
  plasma,
  jet,
  cold_hot,
  red_yellow,
  blue_lightblue
};

// A rectangle in world space; with a volume it shows that volume's values through window/level.
struct PlaneObject {
  std::string name;
  glm::dvec3 center{0.0};
  glm::dvec3 normal{0.0, 0.0, 1.0};
  glm::dvec3 up{0.0, 1.0, 0.0};    // in-plane direction of the rectangle's height
  glm::dvec2 size{200.0, 200.0};   // mm
  int volume = -1;                 // index into Scene::volumes, or -1
  glm::dvec2 window{40.0, 400.0};  // centre, width (data values)
  glm::vec3 color{1.0f};           // multiplies the grey value; the colour when there is no volume
  Colormap colormap = Colormap::grey;  // the windowed value's colour, before `color`
  // Values below it (|value| below it when symmetric) show nothing: what lies behind shows.
  std::optional<double> threshold;
  bool symmetric = false;
  float opacity = 1.0f;
  std::optional<double> thickness;
  SlabProjection slab;  // a thick slab of its volume's values, projected on the plane
};

// How a streamline object colours its tubes.
enum class StreamlineColouring : uint8_t {
  direction,             // |dx|, |dy|, |dz| of the local segment (directionally encoded colour)
  streamline_direction,  // the same of the whole streamline (first to last point)
  fixed,                 // StreamlineObject::color
  point_value,           // a per-point value through the colour map
  streamline_value,      // a per-streamline value through the colour map
  group                  // the colour of the streamline's first group (TRX), else `color`
};

// Which streamlines a region keeps: those passing through it, or those avoiding it.
struct StreamlineRegion {
  enum class Shape : uint8_t { sphere, label, mesh } shape = Shape::sphere;
  bool avoid = false;
  glm::dvec3 center{0.0};  // sphere, world mm
  double radius = 0.0;     // sphere, mm
  // label: voxels equal to `label` in a label map; mesh: the inside of a closed mesh.
  std::shared_ptr<const VolumeData> labels;
  int label = 0;
  std::shared_ptr<const Mesh> mesh;
};

class TubeCache;  // the tubes' geometry and its acceleration, built on first use (src/tubes/)

// How a connectome object draws its node spheres and edge tubes: NiiVue's display fields, each
// from the scene object, else the file, else NiiVue's default (docs/streamlines.md).
struct ConnectomeLook {
  float node_scale = 3.0f;                 // sphere radius = node size * node_scale, mm
  float node_min = 0.0f, node_max = 4.0f;  // values at the map's ends; below node_min: hidden
  Colormap node_colormap = Colormap::red_yellow;               // NiiVue's "warm"
  Colormap node_colormap_negative = Colormap::blue_lightblue;  // "winter": negative values
  float edge_scale = 1.0f;                 // tube radius = |weight| * edge_scale, mm
  float edge_min = 2.0f, edge_max = 6.0f;  // |weight| at the map's ends; below edge_min: hidden
  Colormap edge_colormap = Colormap::red_yellow;
  Colormap edge_colormap_negative = Colormap::blue_lightblue;  // of negative weights
};

// A tractogram drawn as tubes: each segment an exact capsule or cone of `radius` mm.
struct StreamlineObject {
  std::string name;
  std::shared_ptr<const Streamlines> streamlines;  // world space, the transform applied
  double radius = 0.5;                             // mm
  StreamlineColouring colouring = StreamlineColouring::direction;
  glm::vec3 color{1.0f};  // fixed colouring, and groups without a colour
  std::string value;      // point_value / streamline_value: the values' name
  Colormap colormap = Colormap::viridis;
  std::optional<glm::dvec2> range;   // the values mapped to the colour map's ends; empty: all
  float opacity = 1.0f;              // per tube crossing
  std::vector<float> group_opacity;  // per StreamlineGroup, overriding `opacity`; may be empty
  Shading shading{true};
  int stride = 1;                         // every stride-th streamline
  double min_length = 0.0;                // mm; shorter streamlines are not drawn
  std::vector<StreamlineRegion> regions;  // all must hold
  std::optional<double> thickness;        // mm; empty means "auto", as for meshes
  std::vector<ClipPlane> clip_planes;     // world; tubes show where all keep, cuts capped
  std::vector<ClipMesh> clip_meshes;      // closed meshes of the scene, as a volume's; capped
  std::shared_ptr<TubeCache> cache;       // shared by copies of the scene; may be null
  // A "connectome" object: these spheres and tubes are drawn instead of streamlines. Then
  // `streamlines` holds the node centres and no streamline, and `radius` the largest sphere or
  // tube radius, so that bounds and depth ranges see it as they see tubes.
  std::shared_ptr<const Connectome> connectome;  // world space, the transform applied
  ConnectomeLook connectome_look;
};

enum class ObjectKind : uint8_t { volume, mesh, plane, streamlines };

// An object in scene order: which list and which entry.
struct ObjectRef {
  ObjectKind kind;
  int index;
};

// Constructive solid geometry over volumes and closed meshes (SPEC §8, docs/csg.md).
enum class CsgOp : uint8_t { primitive, union_of, intersection, difference };

// Where a primitive counts as present: inside its region (a mesh's interior, a volume's box cut
// by its clip planes), or there and where its transfer function gives opacity (volumes only).
enum class CsgPresence : uint8_t { region, opacity };

// One node of a CSG expression: a primitive (an object of the scene) or a binary operator.
struct CsgNode {
  CsgOp op = CsgOp::primitive;
  ObjectRef object{ObjectKind::volume, -1};  // primitive: the object
  CsgPresence presence = CsgPresence::region;
  int a = -1, b = -1;  // operator: its operands, indices into CsgExpression::nodes
};

// The scene's "csg" block as a tree; n-ary operators are folded into binary nodes.
struct CsgExpression {
  std::vector<CsgNode> nodes;
  int root = -1;
};

struct RenderSettings {
  std::string method = "auto";  // a method's name, or auto (resolve_method in render.hpp)
  int spp = 0;                  // samples per pixel, a perfect square; 0 = the method's default
  double step_mm = 0.0;         // ray step; 0 = the method's default
  double reference_step_fraction =
      0.125;                             // reference step as a fraction of the smallest voxel pitch
  double ert_threshold = 0.99;           // early ray termination opacity; 1 disables
  static constexpr int kMaxLayers = 16;  // the largest `layers` and `rt_layers` zslab holds
  int layers = 8;                        // ZT-buffer slabs per pixel (N)
  int rt_layers = 4;                     // RT-buffer surface layers (M)
  int peel_layers = 4;                   // depth-peeling passes per polygon object (L)
  std::string peel_rest =
      "unsorted";  // peel: fragments behind layer L-1 blended unsorted, or "lost"
  // Tube silhouettes cover their part of each pixel: on, off, or auto (on in the zSlab methods)
  std::string tube_coverage = "auto";
  std::string interpolation = "ovi";
  double beta = 1.0;
  std::string skipping = "distance";             // empty-space skipping: none, bricks, distance
  std::string classification = "preintegrated";  // volume samples: preintegrated or post
  // Shading normals: auto (precomputed while their copy is small, volume_acceleration.hpp),
  // precomputed, or on-the-fly.
  std::string gradients = "auto";
  int brick_size = 8;       // cells per brick edge for skipping, along the finest voxel axis
  int k = 8;                // k+-buffer fragments per pixel
  int fragment_cap = 1024;  // dynamic fragment buffer cap per pixel
  std::optional<double> thickness;      // default surface thickness, mm; empty = auto
  std::string slab_format = "rgba32f";  // stored slab colour: rgba32f or rgba8
  std::string last_volume;  // zSlab: the volume rendered last (cast on the fly); empty = auto
  std::string overflow = "greedy";  // zSlab: a full ZT array folds by greedy or tail merging
  // zSlab: every volume at the common step ("common") or each at a step for its own pitch
  std::string sampling = "per-volume";
  bool packets = true;  // mdvr: one-volume scenes march a packet of rays in SIMD lanes; same image
  std::string csg_simplify = "merge";   // clipping-state simplification: none, merge or full
  double csg_presence_threshold = 0.0;  // TF opacity per unit_distance above which a volume counts
  int csg_max_states = 4096;            // normalization stops with an error beyond this
  std::string mixing = "inclusive";     // co-located volumes: inclusive (M1) or exclusive
  // Exclusive mixing: names in priority order; an inner list is a group mixed inclusively.
  // Empty: scene order.
  std::vector<std::vector<std::string>> mixing_priority;
  double mixing_threshold = 0.0;  // exclusive: TF opacity per unit_distance a winner must exceed
  // Not in scene files: the smallest voxel pitch the frame assumes (0: its volumes' own). A
  // process rendering part of a scene (distributed) sets the whole scene's, so that its steps
  // and surface thicknesses are the whole scene's.
  double pitch_mm = 0.0;
};

struct Scene {
  Camera camera;
  ImageSettings image;
  std::vector<Light> lights{Light{}};
  std::vector<VolumeObject> volumes;
  std::vector<MeshObject> meshes;
  std::vector<PlaneObject> planes;
  std::vector<StreamlineObject> streamlines;
  std::vector<ObjectRef> order;      // every object, in the order of the scene file
  std::optional<CsgExpression> csg;  // the "csg" block; empty without one or with "csg": null
  RenderSettings render;
  std::filesystem::path file;      // the scene file, when loaded from one
  std::vector<std::string> notes;  // what loading chose for the user (a series, a mesh's space)
};

// "volume", "mesh", "plane" or "streamlines": what scene files call the kind.
inline const char* object_kind_name(ObjectKind kind) {
  switch (kind) {
    case ObjectKind::volume:
      return "volume";
    case ObjectKind::mesh:
      return "mesh";
    case ObjectKind::plane:
      return "plane";
    case ObjectKind::streamlines:
      return "streamlines";
  }
  return "object";
}
// The name of the object `ref` refers to in `scene` (its index must be in range).
const std::string& object_name(const Scene& scene, const ObjectRef& ref);

// Loads and validates a JSON scene file; relative paths resolve against its folder.
// `overrides` are "json.path=value" assignments applied before validation (--set).
// Throws imx::Error naming the file, the JSON path and the value at fault.
Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});

// Which voxels of a volume object's source to read, from the object's name and the source's
// header: a box within header.dims (VoxelBox::whole(header.dims): all of them).
using VolumeRegionChooser =
    std::function<VoxelBox(const std::string& object, const VolumeHeader& source)>;

// load_scene that reads only part of some volumes (a process rendering bricks of them): each
// volume object's data is the box `region` chooses (read with read_volume_region), and its
// source_dims and region say where that lies in the whole.
Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides,
                 const VolumeRegionChooser& region);

// The same from JSON text; `base_dir` resolves relative paths, `origin` names it in errors.
Scene parse_scene(const std::string& json_text, const std::filesystem::path& base_dir,
                  const std::string& origin, const std::vector<std::string>& overrides = {});

}  // namespace imx
