// Parser for a "mesh" object: a mesh file or a primitive, its transform, material and interior.
#include <exception>
#include <new>
#include <system_error>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/limits.hpp"
#include "io/mesh/mesh_space.hpp"
#include "phantoms/mesh_primitives.hpp"
#include "scene/mesh_overlay.hpp"
#include "scene/scene_parsers.hpp"

namespace imx::scene_json {
namespace {

constexpr int kDefaultSegments = 64;

int segments(const JsonReader& src) {
  if (auto v = src.find("segments")) return v->integer(3, kMaxPrimitiveSegments);
  return kDefaultSegments;
}

// A size given as one number (all edges equal) or as `n` numbers.
std::vector<double> sizes(const JsonReader& r, size_t n) {
  if (r.json().is_number()) return std::vector<double>(n, r.number(Range::length()));
  if (!r.json().is_array())
    r.fail(fmt::format("expected a positive number or an array of {} positive numbers, got {}", n,
                       r.describe()));
  return r.numbers(n, Range::length());
}

// Tessellates with fields already read: the memory budget's refusal (or the machine's) is
// reported at the primitive's JSON path.
template <class Make>
Mesh tessellated(const JsonReader& src, Make&& make) {
  try {
    return make();
  } catch (const std::bad_alloc&) {
    src.fail(out_of_memory_message("the primitive"));
  } catch (const Error& e) {
    src.fail(e.what());
  }
}

Mesh make_primitive(const JsonReader& src) {
  const std::string kind =
      src.get("primitive").choice({"sphere", "box", "cylinder", "torus", "quad"});
  if (kind == "sphere") {
    src.check_keys({"primitive", "radius", "segments"});
    const double radius = src.get("radius").number(Range::length());
    const int n = segments(src);
    return tessellated(src, [&] { return make_sphere(radius, n); });
  }
  if (kind == "box") {
    src.check_keys({"primitive", "size"});
    std::vector<double> s = sizes(src.get("size"), 3);
    return make_box({s[0], s[1], s[2]});
  }
  if (kind == "cylinder") {
    src.check_keys({"primitive", "radius", "height", "segments"});
    const double radius = src.get("radius").number(Range::length());
    const double height = src.get("height").number(Range::length());
    const int n = segments(src);
    return tessellated(src, [&] { return make_cylinder(radius, height, n); });
  }
  if (kind == "torus") {
    src.check_keys({"primitive", "major_radius", "minor_radius", "segments"});
    double major = src.get("major_radius").number(Range::length());
    JsonReader minor_reader = src.get("minor_radius");
    double minor = minor_reader.number(Range::length());
    if (minor >= major)
      minor_reader.fail(
          fmt::format("{} must be less than major_radius {} (the torus would "
                      "intersect itself)",
                      minor, major));
    const int n = segments(src);
    return tessellated(src, [&] { return make_torus(major, minor, n); });
  }
  src.check_keys({"primitive", "size"});
  std::vector<double> s = sizes(src.get("size"), 2);
  return make_quad({s[0], s[1]});
}

// The note for a space that the file chose, or that nothing chose (the scene's space, LPS
// unless it says "space": "RAS"): empty when the mesh's "space" chose it.
std::string space_note(const std::string& name, const std::filesystem::path& file,
                       const MeshFileInfo& info, MeshSpace world) {
  const std::string shown = file.filename().string();
  if (info.space_source == MeshSpaceSource::assumed)
    return fmt::format(
        "mesh '{}': {} names no space (no SPACE= header) and its source no \"space\": {} assumed "
        "(the scene's){}",
        name, shown, mesh_space_name(world), world == MeshSpace::ras ? "; converted to LPS" : "");
  const std::string to = info.space == MeshSpace::ras ? "converted to LPS" : "used as it is";
  if (info.space_source == MeshSpaceSource::header)
    return fmt::format("mesh '{}': {} says SPACE={}; {}", name, shown, mesh_space_name(info.space),
                       to);
  if (info.space_source == MeshSpaceSource::format)
    return fmt::format("mesh '{}': {} is {}, whose coordinates are RAS; {}", name, shown,
                       file.extension() == ".gii" ? "GIfTI" : "a FreeSurfer surface", to);
  return {};
}

// The mesh a "source" names, in LPS and its own units (files are read once per scene and set
// of reading options; the note on its space is given for the first object that reads it).
std::shared_ptr<const Mesh> load_mesh_source(const JsonReader& src, const std::string& name,
                                             SceneContext& context) {
  if (!context.given_volumes.empty() && src.json().is_object() && src.has("$volume"))
    src.fail("is a volume the program gave, not a mesh");
  if (!context.given_meshes.empty() && src.json().is_object() && src.has("$mesh")) {
    src.check_keys({"$mesh"});
    JsonReader id = src.get("$mesh");
    auto it = context.given_meshes.find(id.string());
    if (it == context.given_meshes.end()) id.fail(id.text() + " is not a mesh of this scene");
    return it->second;
  }
  // Every key a source may have first, so that a misspelt "file" gets a suggestion.
  src.check_keys({"file", "primitive", "radius", "size", "height", "major_radius", "minor_radius",
                  "segments", "space", "crease_angle_deg"});
  const bool file = src.has("file"), primitive = src.has("primitive");
  if (file == primitive)
    src.fail(file ? "give either \"file\" or \"primitive\", not both"
                  : "needs \"file\" (a mesh file) or \"primitive\" (sphere, box, cylinder, "
                    "torus or quad)");
  if (primitive) {
    for (const char* key : {"space", "crease_angle_deg"})
      if (auto v = src.find(key))
        v->fail(
            fmt::format("\"{}\" applies to mesh files; primitives are made in LPS with "
                        "their own normals",
                        key));
    // Made in LPS whatever the scene's space: every primitive is centred at the origin and
    // symmetric about z, so the RAS-LPS turn (180 degrees about z) would give the same shape.
    const std::string key = "primitive:" + src.json().dump();
    context.used.insert(key);
    if (auto it = context.meshes.find(key); it != context.meshes.end()) return it->second;
    auto mesh = std::make_shared<const Mesh>(make_primitive(src));
    context.meshes.emplace(key, mesh);
    return mesh;
  }
  src.check_keys({"file", "space", "crease_angle_deg"});
  MeshReadOptions options;
  if (auto v = src.find("space"))
    options.space = v->choice({"LPS", "RAS"}) == "RAS" ? MeshSpace::ras : MeshSpace::lps;
  if (auto v = src.find("crease_angle_deg"))
    options.crease_angle_deg = v->number(Range::closed(0.0, 180.0));
  JsonReader file_reader = src.get("file");
  std::filesystem::path path = context.resolve_file(file_reader);
  std::error_code ec;
  std::filesystem::path canonical = std::filesystem::weakly_canonical(path, ec);
  std::string key = fmt::format("{}\n{}\n{}", (ec ? path : canonical).string(),
                                options.space ? mesh_space_name(*options.space)
                                : context.world_space == MeshSpace::ras ? "file, else RAS"
                                                                        : "file",
                                options.crease_angle_deg);
  context.used.insert(key);
  if (auto it = context.meshes.find(key); it != context.meshes.end()) return it->second;
  auto mesh = file_reader.reading(path.string(), [&] {
    MeshFile read = read_mesh_file(path, options);
    if (read.info.space_source == MeshSpaceSource::assumed && context.world_space == MeshSpace::ras)
      detail::flip_ras_lps(read.mesh);
    if (std::string note = space_note(name, path, read.info, context.world_space); !note.empty())
      context.notes.push_back(std::move(note));
    for (const std::string& note : read.info.notes)
      context.notes.push_back(fmt::format("mesh '{}': {}", name, note));
    // The file's vertex map and point data stay with the mesh, for "overlay".
    return share_mesh_file(std::move(read));
  });
  context.meshes.emplace(key, mesh);
  return mesh;
}

// A mesh from a file whose source gives no "space": its space is checked against the volumes
// once the scene is read (mesh_space_evidence.hpp).
void add_space_candidate(const JsonReader& src, const std::string& name,
                         const std::shared_ptr<const Mesh>& mesh, const glm::dmat4& transform,
                         SceneContext& context) {
  const MeshFile* file = mesh_file_of(mesh);
  if (file == nullptr || !src.has("file") || src.has("space")) return;
  const MeshFileInfo& info = file->info;
  MeshSpaceCandidate c;
  c.name = name;
  c.file = context.resolve_file(src.get("file")).filename().string();
  c.mesh = mesh;
  c.transform = transform;
  c.read_as = info.space;
  switch (info.space_source) {
    case MeshSpaceSource::assumed:
      c.read_as = context.world_space;
      c.why = "it names no space, so the scene's";
      break;
    case MeshSpaceSource::header:
      c.why = fmt::format("it says SPACE={}", mesh_space_name(info.space));
      break;
    case MeshSpaceSource::format:
      c.why = "its format's coordinates are RAS";
      break;
    case MeshSpaceSource::option:
      return;
  }
  context.mesh_space_candidates.push_back(std::move(c));
}

Material parse_material(const JsonReader& r) {
  r.check_keys({"color", "opacity", "shading"});
  Material m;
  if (auto v = r.find("color")) m.color = v->color();
  if (auto v = r.find("opacity"))
    m.opacity = static_cast<float>(v->number(Range::closed(0.0, 1.0)));
  if (auto v = r.find("shading")) m.shading = parse_shading(*v);
  return m;
}

// The medium inside a closed mesh; load_scene checks that the mesh is a CSG primitive.
MeshInterior parse_interior(const JsonReader& r) {
  r.check_keys({"color", "opacity", "unit_distance"});
  MeshInterior interior;
  if (auto v = r.find("color")) interior.color = v->color();
  if (auto v = r.find("opacity"))
    interior.opacity = static_cast<float>(v->number(Range::closed(0.0, 1.0)));
  if (auto v = r.find("unit_distance")) interior.unit_distance = v->number(Range::length());
  return interior;
}

}  // namespace

MeshObject parse_mesh_object(const JsonReader& r, SceneContext& context) {
  r.check_keys({"name", "type", "source", "transform", "material", "thickness", "interior",
                "visible", "overlay", "color_by"});
  MeshObject m;
  m.name = r.get("name").string();
  glm::dmat4 transform(1.0);
  if (auto t = r.find("transform")) transform = parse_transform(*t, context);
  if (auto v = r.find("material")) m.material = parse_material(*v);
  if (auto v = r.find("thickness")) m.thickness = parse_thickness(*v);
  if (auto v = r.find("interior")) m.interior = parse_interior(*v);
  // Hidden: nothing shows, yet the mesh still clips volumes and takes part in CSG.
  if (!parse_visible(r)) {
    m.material.opacity = 0.0f;
    if (m.interior) m.interior->opacity = 0.0f;
  }
  std::shared_ptr<const Mesh> mesh = load_mesh_source(r.get("source"), m.name, context);
  add_space_candidate(r.get("source"), m.name, mesh, transform, context);
  // Values on the mesh colour its vertices before it is placed ("color_by" comes after every
  // object is read: apply_color_by).
  if (auto v = r.find("overlay")) {
    const JsonReader src = r.get("source");  // a CIFTI overlay asks the surface file what it is
    mesh = apply_overlay(
        *v, mesh, context,
        src.has("file") ? context.resolve_file(src.get("file")) : std::filesystem::path());
  }
  // One placed copy per source and transform, so that a scene parsed again keeps its meshes.
  std::string key = fmt::format("{}", static_cast<const void*>(mesh.get()));
  for (int c = 0; c < 4; ++c)
    for (int row = 0; row < 4; ++row) key += fmt::format(" {}", transform[c][row]);
  context.used.insert(key);
  auto [it, fresh] = context.placed_meshes.try_emplace(key);
  // The identity places the mesh as it is: no second copy of a large mesh.
  if (fresh)
    it->second = transform == glm::dmat4(1.0)
                     ? mesh
                     : std::make_shared<const Mesh>(transform_mesh(*mesh, transform));
  m.mesh = it->second;
  return m;
}

}  // namespace imx::scene_json
