#include "raster/rasterizer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/blinn_phong.hpp"
#include "core/math.hpp"
#include "intermix/error.hpp"
#include "presets/colormap.hpp"
#include "raster/clip_polygon.hpp"
#include "raster/edge_function.hpp"
#include "raster/shade_fragment.hpp"
#include "raster/slab_sample.hpp"
#include "tubes/tube_cache.hpp"
#include "tubes/tube_coverage.hpp"
#include "tubes/tube_fragments.hpp"

namespace imx {

namespace {

// Larger sample sets than 32x32 per pixel are not meaningful and would not fit the stack tables.
constexpr size_t kMaxSamples = 1024;
// Larger images would overflow the 64-bit fixed-point edge functions (with the guard band).
constexpr int kMaxImageSize = 1 << 15;
// Marks a covered sample that turned out to have no fragment (object ids never reach it).
constexpr uint32_t kHole = UINT32_MAX;
// Above this many fragments per sample the insertion sort hands over to std::stable_sort.
constexpr uint32_t kInsertionSortLimit = 32;

int64_t floor_div(int64_t a, int64_t b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}
int64_t ceil_div(int64_t a, int64_t b) {
  return -floor_div(-a, b);
}

// What a fragment of one scene object looks like.
struct ObjectInfo {
  uint32_t order_index = 0;  // index into Scene::order, the fragment's object id
  bool is_plane = false;
  bool shaded = true;  // false: only depth and facing are needed (clip meshes for the clip step)
  // Mesh.
  Material material;
  bool has_normals = false;
  bool has_colors = false;  // per-vertex colours scale the material colour
  // Its triangles' setup is made again per tile from the mesh, not stored per triangle.
  std::shared_ptr<const Mesh> mesh;
  uint32_t raster_begin = 0;  // its clipped triangles start at this index of Impl::triangles
  // Plane.
  glm::vec3 plane_color{1.0f};
  float plane_opacity = 1.0f;
  const PreparedVolume* volume = nullptr;
  float window_centre = 0.0f, window_width = 1.0f;
  Colormap colormap = Colormap::grey;
  float threshold = -std::numeric_limits<float>::infinity();  // plane_value_shown
  bool symmetric = false;
  int slab_samples = 1;       // a thick slab's samples along the normal (1: the plane alone)
  glm::vec3 slab_step{0.0f};  // index-space step between them
  SlabMode slab_mode = SlabMode::mip;
};

// One input triangle before clipping: its plane in camera space and its shading attributes.
struct SourceTriangle {
  glm::dvec3 normal{0.0};              // unit geometric normal, camera space
  double offset = 0.0;                 // dot(normal, p) for every camera-space point p of the plane
  glm::dvec3 corner{0.0};              // camera-space first vertex
  glm::vec3 dual1{0.0f}, dual2{0.0f};  // barycentrics: b_i = dot(dual_i, p - corner)
  std::array<glm::vec3, 3> normals;    // world-space vertex normals, or the geometric normal x3
  std::array<glm::vec3, 3> colors;     // linear vertex colours (ObjectInfo::has_colors only)
  uint32_t object = 0;                 // index into Impl::objects
  uint32_t front_facing = 0;
};

// One clipped triangle: fixed-point image corners (guard-banded, so they fit 32 bits); its edges
// and bounds are set up again where used, which costs less than storing them for 10 M triangles.
struct RasterTriangle {
  int32_t x[3], y[3];
  uint32_t source = 0;  // a mesh's triangle index, or a plane's index into Impl::sources
};

// A mesh vertex as its triangles' setup needs it, made once per vertex (12 bytes: the camera
// position is made again for the few triangles the clipper cuts).
struct VertexSetup {
  int32_t x = 0, y = 0;  // snapped image position, where every clip plane has it inside
  uint32_t inside = 0;   // bit i: inside clip plane i
};

FixedPoint corner_of(const RasterTriangle& rt, int i) {
  return {rt.x[i], rt.y[i]};
}

struct FixedBounds {
  int64_t min_x, min_y, max_x, max_y;
};

inline FixedBounds bounds_of(const RasterTriangle& rt) {
  return {
      std::min(rt.x[0], std::min(rt.x[1], rt.x[2])), std::min(rt.y[0], std::min(rt.y[1], rt.y[2])),
      std::max(rt.x[0], std::max(rt.x[1], rt.x[2])), std::max(rt.y[0], std::max(rt.y[1], rt.y[2]))};
}

// The pixel span [lo, hi] whose samples (at fixed-point offsets [o_lo, o_hi]) can fall in
// the fixed-point interval [min, max].
void pixel_span(int64_t min, int64_t max, int64_t o_lo, int64_t o_hi, int64_t& lo, int64_t& hi) {
  lo = ceil_div(min - o_hi, kSubpixelScale);
  hi = floor_div(max - o_lo, kSubpixelScale);
}

}  // namespace

struct Rasterizer::Impl {
  CameraModel camera;
  int width = 0, height = 0, tile_size = 0, tiles_x = 0, tiles_y = 0;
  // Image position = origin + scale * (x, y) / z (perspective) or * (x, y) (orthographic).
  glm::dvec2 image_origin{0.0}, image_scale{1.0};
  std::vector<ClipPlaneEq> clip_planes;
  std::vector<ShadingLight> lights;
  std::vector<ObjectInfo> objects;
  std::vector<SourceTriangle> sources;
  std::vector<RasterTriangle> triangles;
  std::vector<uint32_t> bin_offsets;  // tile b owns bin_items[bin_offsets[b] .. bin_offsets[b+1])
  std::vector<uint32_t> bin_items;
  // Streamline objects: their tubes are ray-traced per sample, not binned (src/tubes/).
  struct Tubes {
    StreamlineObject object;  // a copy: the scene need not outlive the rasterizer
    std::shared_ptr<const TubeGeometry> geometry;
    TubeLook look;
    uint32_t order_index = 0;
  };
  std::vector<std::unique_ptr<Tubes>> tubes;

  explicit Impl(const CameraModel& c) : camera(c) {}

  // The plane and shading of a triangle; false when it shows nothing (degenerate, edge-on).
  bool make_source(const std::array<glm::dvec3, 3>& world, const std::array<glm::dvec3, 3>& cam,
                   const std::array<glm::vec3, 3>* vertex_normals,
                   const std::array<glm::vec3, 3>* vertex_colors, uint32_t object,
                   SourceTriangle& src) const;
  // Triangle `t` of mesh object `object`, set up as make_source does from the same numbers.
  bool mesh_source(uint32_t object, uint32_t t, SourceTriangle& src) const;
  VertexSetup setup_vertex(const glm::dvec3& cam) const;
  FixedPoint snap(const glm::dvec3& cam) const;
  // Appends the clipped, snapped pieces of a camera-space triangle that are on screen;
  // `cam_of(i)` gives corner i in camera space, asked only where the clipper cuts.
  template <class CamOf>
  void add_pieces(const std::array<const VertexSetup*, 3>& v, const CamOf& cam_of, uint32_t source,
                  std::vector<RasterTriangle>& out) const;
  void add_fan(const FixedPoint* fixed, int n, uint32_t source,
               std::vector<RasterTriangle>& out) const;
  void add_triangle(const std::array<glm::dvec3, 3>& world, const std::array<glm::dvec3, 3>& cam,
                    uint32_t object);
  void add_mesh(const std::string& name, uint32_t object, std::vector<VertexSetup>& vertices);
  // The object whose clipped triangles include `item`.
  uint32_t object_of(uint32_t item) const {
    auto it = std::upper_bound(objects.begin(), objects.end(), item,
                               [](uint32_t i, const ObjectInfo& o) { return i < o.raster_begin; });
    return static_cast<uint32_t>(it - objects.begin()) - 1;
  }
  void build_bins();
  void add_tube_fragments(const TileRect& tile, std::span<const glm::vec2> offsets,
                          SampleFragments& out) const;

  // Screen coordinates of image position (px, py): its ray's camera-space direction (x/z, y/z)
  // in perspective, its ray's camera-space origin (x, y) in orthographic.
  glm::dvec2 screen(double px, double py) const {
    return {(px - image_origin.x) / image_scale.x, (py - image_origin.y) / image_scale.y};
  }

  // The fragment of `src` for the sample at image position (px, py), which its edges cover;
  // false when the ray misses its plane in front of the eye or a plane's volume there.
  bool make_fragment(const SourceTriangle& src, const ObjectInfo& obj, double px, double py,
                     Fragment& f) const {
    // Depth from the exact (unsnapped) sample position.
    const glm::dvec2 s = screen(px, py);
    double t;
    glm::dvec3 hit;
    if (!intersect(src, s, t, hit)) return false;
    f.t = static_cast<float>(t);
    f.object = obj.order_index;
    f.front_facing = src.front_facing;
    if (!obj.shaded) {
      f.color = glm::vec4(0.0f);
      return true;
    }
    if (obj.is_plane) {
      float grey = 1.0f;
      if (obj.volume && obj.volume->labels.active()) {  // a label plane: the table's colours
        glm::vec3 rgb;
        if (!sample_plane_labels(*obj.volume, glm::vec3(camera.to_world(hit)), rgb)) return false;
        f.color = shade_plane_fragment(obj.plane_color, obj.plane_opacity, rgb);
        return true;
      }
      if (obj.volume && obj.volume->colours.active()) {  // a colour volume: its own colours
        glm::vec3 rgb;
        if (!sample_plane_colour(*obj.volume, glm::vec3(camera.to_world(hit)), rgb)) return false;
        f.color = shade_plane_fragment(obj.plane_color, obj.plane_opacity, rgb);
        return true;
      }
      if (obj.volume) {
        float value = 0.0f;
        const glm::vec3 world(camera.to_world(hit));
        if (obj.slab_samples > 1
                ? !sample_plane_slab(*obj.volume, obj.volume->to_index(world), obj.slab_step,
                                     obj.slab_samples, obj.slab_mode, value)
                : !sample_plane_volume(*obj.volume, world, value))
          return false;
        if (!plane_value_shown(value, obj.threshold, obj.symmetric)) return false;
        // The window's grey level through the plane's colour map (grey: a display grey).
        f.color = shade_plane_fragment(
            obj.plane_color, obj.plane_opacity,
            colormap_rgb(obj.colormap, window_level(value, obj.window_centre, obj.window_width)));
        return true;
      }
      f.color = shade_plane_fragment(obj.plane_color, obj.plane_opacity, grey);
      return true;
    }
    glm::vec3 normal = src.normals[0];
    glm::vec3 base = obj.material.color;
    const bool smooth = obj.material.shading.enabled && obj.has_normals;
    if (smooth || obj.has_colors) {
      // Barycentrics of the 3D hit point: perspective-correct by construction.
      glm::vec3 rel(hit - src.corner);
      float b1 = std::max(0.0f, glm::dot(src.dual1, rel));
      float b2 = std::max(0.0f, glm::dot(src.dual2, rel));
      float b0 = std::max(0.0f, 1.0f - b1 - b2);
      const float inv = 1.0f / std::max(b0 + b1 + b2, 1e-12f);
      if (smooth) normal = (b0 * src.normals[0] + b1 * src.normals[1] + b2 * src.normals[2]) * inv;
      if (obj.has_colors)
        base *= (b0 * src.colors[0] + b1 * src.colors[1] + b2 * src.colors[2]) * inv;
    }
    glm::dvec3 dir =
        camera.perspective()
            ? glm::normalize(s.x * camera.right() + s.y * camera.up() + camera.forward())
            : camera.forward();
    f.color = shade_mesh_fragment(obj.material, base, normal, -glm::vec3(dir), lights);
    return true;
  }

  // Depth t and camera-space point where the sample ray at screen (sx, sy) meets the
  // triangle's plane; false when it does not in front of the eye.
  bool intersect(const SourceTriangle& tri, const glm::dvec2& s, double& t, glm::dvec3& p) const {
    const glm::dvec3& n = tri.normal;
    if (camera.perspective()) {
      glm::dvec3 d(s.x, s.y, 1.0);
      double rate = glm::dot(n, d);
      double along = tri.offset / rate;
      if (!(along > 0.0) || !std::isfinite(along)) return false;
      p = along * d;
      t = along * std::sqrt(glm::dot(d, d));
    } else {
      double z = (tri.offset - n.x * s.x - n.y * s.y) / n.z;
      if (!(z >= 0.0) || !std::isfinite(z)) return false;
      p = glm::dvec3(s.x, s.y, z);
      t = z;
    }
    return true;
  }
};

bool Rasterizer::Impl::make_source(const std::array<glm::dvec3, 3>& world,
                                   const std::array<glm::dvec3, 3>& cam,
                                   const std::array<glm::vec3, 3>* vertex_normals,
                                   const std::array<glm::vec3, 3>* vertex_colors, uint32_t object,
                                   SourceTriangle& src) const {
  glm::dvec3 n_world = glm::cross(world[1] - world[0], world[2] - world[0]);
  double len = glm::length(n_world);
  if (!(len > 0.0) || !std::isfinite(len)) return false;  // degenerate or non-finite
  n_world /= len;

  // Rotating the world normal keeps its orientation; camera space is left-handed, so a cross
  // product of camera-space edges would flip it.
  src.normal = glm::dvec3(glm::dot(n_world, camera.right()), glm::dot(n_world, camera.up()),
                          glm::dot(n_world, camera.forward()));
  src.offset = glm::dot(src.normal, cam[0]);
  if (camera.perspective() ? src.offset == 0.0 : src.normal.z == 0.0) return false;  // edge-on
  src.front_facing = (camera.perspective() ? src.offset < 0.0 : src.normal.z < 0.0) ? 1u : 0u;
  src.corner = cam[0];
  glm::dvec3 e1 = cam[1] - cam[0], e2 = cam[2] - cam[0];
  double d00 = glm::dot(e1, e1), d01 = glm::dot(e1, e2), d11 = glm::dot(e2, e2);
  double den = d00 * d11 - d01 * d01;
  if (!(den > 0.0)) return false;
  src.dual1 = glm::vec3((d11 * e1 - d01 * e2) / den);
  src.dual2 = glm::vec3((d00 * e2 - d01 * e1) / den);
  if (vertex_normals)
    src.normals = *vertex_normals;
  else
    src.normals.fill(glm::vec3(n_world));
  if (vertex_colors) src.colors = *vertex_colors;
  src.object = object;
  return true;
}

bool Rasterizer::Impl::mesh_source(uint32_t object, uint32_t t, SourceTriangle& src) const {
  const ObjectInfo& obj = objects[object];
  const Mesh& mesh = *obj.mesh;
  const glm::uvec3& tri = mesh.triangles[t];
  std::array<glm::dvec3, 3> world, cam;
  std::array<glm::vec3, 3> normals, colors;
  for (int c = 0; c < 3; ++c) {
    world[c] = glm::dvec3(mesh.positions[tri[c]]);
    cam[c] = camera.to_camera(world[c]);
    if (obj.has_normals) normals[c] = mesh.normals[tri[c]];
    if (obj.has_colors) colors[c] = mesh.colors[tri[c]];
  }
  return make_source(world, cam, obj.has_normals ? &normals : nullptr,
                     obj.has_colors ? &colors : nullptr, object, src);
}

FixedPoint Rasterizer::Impl::snap(const glm::dvec3& cam) const {
  const double guard = static_cast<double>(std::max(width, height));
  glm::dvec2 q = camera.project_camera(cam);
  // Clipping leaves points on the guard band up to rounding; the clamp bounds the integers.
  q.x = std::clamp(q.x, -guard - 1.0, width + guard + 1.0);
  q.y = std::clamp(q.y, -guard - 1.0, height + guard + 1.0);
  return snap_to_subpixel(q);
}

VertexSetup Rasterizer::Impl::setup_vertex(const glm::dvec3& cam) const {
  VertexSetup v;
  for (size_t i = 0; i < clip_planes.size(); ++i)
    v.inside |= clip_distance(clip_planes[i], cam) >= 0.0 ? 1u << i : 0u;
  if (v.inside == (1u << clip_planes.size()) - 1) {
    const FixedPoint f = snap(cam);
    v.x = static_cast<int32_t>(f.x);
    v.y = static_cast<int32_t>(f.y);
  }
  return v;
}

template <class CamOf>
void Rasterizer::Impl::add_pieces(const std::array<const VertexSetup*, 3>& v, const CamOf& cam_of,
                                  uint32_t source, std::vector<RasterTriangle>& out) const {
  // Trivial accept/reject before paying for the clipper.
  const uint32_t all = (1u << clip_planes.size()) - 1;
  if ((v[0]->inside | v[1]->inside | v[2]->inside) != all) return;  // all outside one plane
  if ((v[0]->inside & v[1]->inside & v[2]->inside) == all) {
    const FixedPoint fixed[3] = {{v[0]->x, v[0]->y}, {v[1]->x, v[1]->y}, {v[2]->x, v[2]->y}};
    add_fan(fixed, 3, source, out);
    return;
  }
  ClipPolygon poly;
  poly.n = 3;
  for (int i = 0; i < 3; ++i) poly.v[i] = cam_of(i);
  for (const ClipPlaneEq& plane : clip_planes) {
    clip_polygon(poly, plane);
    if (poly.n < 3) return;
  }
  std::array<FixedPoint, ClipPolygon::kCapacity> fixed;
  for (int i = 0; i < poly.n; ++i) fixed[i] = snap(poly.v[i]);
  add_fan(fixed.data(), poly.n, source, out);
}

void Rasterizer::Impl::add_fan(const FixedPoint* fixed, int n, uint32_t source,
                               std::vector<RasterTriangle>& out) const {
  for (int i = 1; i + 1 < n; ++i) {  // fan: the shared diagonals are exact in fixed point
    const FixedPoint corners[3] = {fixed[0], fixed[i], fixed[i + 1]};
    if (twice_area(corners) == 0) continue;  // setup_triangle_edges would refuse it
    RasterTriangle rt;
    for (int c = 0; c < 3; ++c) {
      rt.x[c] = static_cast<int32_t>(corners[c].x);
      rt.y[c] = static_cast<int32_t>(corners[c].y);
    }
    const FixedBounds b = bounds_of(rt);
    int64_t x0, x1, y0, y1;
    pixel_span(b.min_x, b.max_x, 0, kSubpixelScale, x0, x1);
    pixel_span(b.min_y, b.max_y, 0, kSubpixelScale, y0, y1);
    if (x1 < 0 || y1 < 0 || x0 >= width || y0 >= height) continue;  // off screen
    rt.source = source;
    out.push_back(rt);
  }
}

void Rasterizer::Impl::add_triangle(const std::array<glm::dvec3, 3>& world,
                                    const std::array<glm::dvec3, 3>& cam, uint32_t object) {
  SourceTriangle src;
  if (!make_source(world, cam, nullptr, nullptr, object, src)) return;
  const size_t before = triangles.size();
  const VertexSetup v[3] = {setup_vertex(cam[0]), setup_vertex(cam[1]), setup_vertex(cam[2])};
  add_pieces(
      {&v[0], &v[1], &v[2]}, [&](int i) { return cam[i]; }, static_cast<uint32_t>(sources.size()),
      triangles);
  if (triangles.size() > before) sources.push_back(src);
}

void Rasterizer::Impl::add_mesh(const std::string& name, uint32_t object,
                                std::vector<VertexSetup>& vertices) {
  const Mesh& mesh = *objects[object].mesh;
  const size_t n_vertices = mesh.positions.size(), n = mesh.triangles.size();
  // One transform and projection per vertex: shared edges then clip and snap bit-identically.
  vertices.resize(n_vertices);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n_vertices), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i)
      vertices[i] = setup_vertex(camera.to_camera(glm::dvec3(mesh.positions[i])));
  });
  // Blocks of chunks set up in parallel, appended in triangle order: the pieces in flight stay
  // a block's worth, whatever the mesh's size.
  constexpr size_t kChunk = size_t{1} << 14, kBlock = 64 * kChunk;
  std::vector<std::vector<RasterTriangle>> pieces(kBlock / kChunk);
  std::vector<size_t> first_bad(pieces.size());
  for (size_t b0 = 0; b0 < n; b0 += kBlock) {
    const size_t b1 = std::min(n, b0 + kBlock), chunks = (b1 - b0 + kChunk - 1) / kChunk;
    tbb::parallel_for(size_t{0}, chunks, [&](size_t c) {
      std::vector<RasterTriangle>& out = pieces[c];
      out.clear();
      first_bad[c] = SIZE_MAX;
      for (size_t t = b0 + c * kChunk; t < std::min(b1, b0 + (c + 1) * kChunk); ++t) {
        const glm::uvec3& tri = mesh.triangles[t];
        if (std::max({tri.x, tri.y, tri.z}) >= n_vertices) {
          first_bad[c] = t;
          return;
        }
        const std::array<const VertexSetup*, 3> v = {&vertices[tri.x], &vertices[tri.y],
                                                     &vertices[tri.z]};
        // Not make_source here: the rare triangle it refuses (degenerate, edge-on) is refused
        // per tile instead, its covered samples left as holes, so the fragments are the same.
        add_pieces(
            v, [&](int i) { return camera.to_camera(glm::dvec3(mesh.positions[tri[i]])); },
            static_cast<uint32_t>(t), out);
      }
    });
    for (size_t c = 0; c < chunks; ++c)
      if (first_bad[c] != SIZE_MAX) {
        const glm::uvec3& tri = mesh.triangles[first_bad[c]];
        const uint32_t bad = tri.x >= n_vertices ? tri.x : tri.y >= n_vertices ? tri.y : tri.z;
        throw Error(fmt::format("mesh '{}': triangle {} refers to vertex {} of {}", name,
                                first_bad[c], bad, n_vertices));
      }
    std::vector<size_t> at(chunks + 1, triangles.size());
    for (size_t c = 0; c < chunks; ++c) at[c + 1] = at[c] + pieces[c].size();
    triangles.resize(at[chunks]);
    tbb::parallel_for(size_t{0}, chunks, [&](size_t c) {
      std::copy(pieces[c].begin(), pieces[c].end(), triangles.begin() + at[c]);
    });
  }
}

void Rasterizer::Impl::build_bins() {
  const size_t tile_count = static_cast<size_t>(tiles_x) * tiles_y;
  // A shift for the usual power-of-two tiles: a division per corner was a tenth of the bins.
  const bool power_of_two = (tile_size & (tile_size - 1)) == 0;
  const int shift = std::countr_zero(static_cast<unsigned>(tile_size));
  auto tile_of = [&](int64_t pixel) {
    return static_cast<int>(power_of_two ? pixel >> shift : pixel / tile_size);
  };
  auto for_each_tile_of = [&](const RasterTriangle& rt, auto&& fn) {
    const FixedBounds bounds = bounds_of(rt);
    int64_t x0, x1, y0, y1;
    pixel_span(bounds.min_x, bounds.max_x, 0, kSubpixelScale, x0, x1);
    pixel_span(bounds.min_y, bounds.max_y, 0, kSubpixelScale, y0, y1);
    const int tx0 = tile_of(std::max<int64_t>(x0, 0)),
              tx1 = tile_of(std::min<int64_t>(x1, width - 1));
    const int ty0 = tile_of(std::max<int64_t>(y0, 0)),
              ty1 = tile_of(std::min<int64_t>(y1, height - 1));
    for (int ty = ty0; ty <= ty1; ++ty)
      for (int tx = tx0; tx <= tx1; ++tx) fn(static_cast<size_t>(ty) * tiles_x + tx);
  };
  // Chunks of triangles count, then fill, in parallel; chunk c's items of a bin go after those
  // of chunks before it, so every bin stays in triangle (= scene) order.
  const size_t n = triangles.size();
  const size_t chunks = std::clamp<size_t>(n / (size_t{1 << 16} + tile_count), 1, 16);
  const size_t per_chunk = (n + chunks - 1) / chunks;
  std::vector<uint32_t> cursor(chunks * tile_count, 0);
  tbb::parallel_for(size_t{0}, chunks, [&](size_t c) {
    uint32_t* count = cursor.data() + c * tile_count;
    for (size_t i = c * per_chunk; i < std::min(n, (c + 1) * per_chunk); ++i)
      for_each_tile_of(triangles[i], [&](size_t b) { ++count[b]; });
  });
  bin_offsets.assign(tile_count + 1, 0);
  for (size_t b = 0; b < tile_count; ++b) {
    uint32_t at = bin_offsets[b];
    for (size_t c = 0; c < chunks; ++c) {
      const uint32_t count = cursor[c * tile_count + b];
      cursor[c * tile_count + b] = at;
      at += count;
    }
    bin_offsets[b + 1] = at;
  }
  bin_items.resize(bin_offsets[tile_count]);
  tbb::parallel_for(size_t{0}, chunks, [&](size_t c) {
    uint32_t* next = cursor.data() + c * tile_count;
    for (size_t i = c * per_chunk; i < std::min(n, (c + 1) * per_chunk); ++i)
      for_each_tile_of(triangles[i],
                       [&](size_t b) { bin_items[next[b]++] = static_cast<uint32_t>(i); });
  });
}

namespace {

// Per mesh: whether some volume names it in its clip list (SPEC §7); indices out of range are
// ignored here (ClipPlan reports them).
std::vector<bool> clip_meshes(const Scene& scene) {
  std::vector<bool> clips(scene.meshes.size(), false);
  for (const VolumeObject& v : scene.volumes)
    for (const ClipMesh& c : v.clip_meshes)
      if (c.mesh >= 0 && static_cast<size_t>(c.mesh) < clips.size()) clips[c.mesh] = true;
  return clips;
}

// Per mesh: a CSG primitive, whose fragments its method needs whatever its material.
std::vector<bool> csg_meshes(const Scene& scene) {
  std::vector<bool> csg(scene.meshes.size(), false);
  if (scene.csg)
    for (const CsgNode& n : scene.csg->nodes)
      if (n.op == CsgOp::primitive && n.object.kind == ObjectKind::mesh && n.object.index >= 0 &&
          static_cast<size_t>(n.object.index) < csg.size())
        csg[n.object.index] = true;
  return csg;
}

}  // namespace

std::vector<bool> shown_meshes(const Scene& scene) {
  const std::vector<bool> csg = csg_meshes(scene);
  std::vector<bool> shown(scene.meshes.size());
  for (size_t m = 0; m < shown.size(); ++m)
    shown[m] = scene.meshes[m].material.opacity > 0.0f || csg[m];
  return shown;
}

bool shown_plane(const PlaneObject& plane) {
  return plane.opacity > 0.0f;
}

Rasterizer::Rasterizer(const Scene& scene, const CameraModel& camera,
                       std::span<const PreparedVolume> volumes, int tile_size,
                       RasterObjects objects, bool tube_coverage)
    : tile_size_(tile_size) {
  if (tile_size <= 0)
    throw Error(fmt::format("rasterizer: tile size {} must be positive", tile_size));
  if (camera.width() > kMaxImageSize || camera.height() > kMaxImageSize)
    throw Error(fmt::format("rasterizer: image size {}x{} exceeds {} pixels", camera.width(),
                            camera.height(), kMaxImageSize));
  auto impl = std::make_shared<Impl>(camera);
  Impl& im = *impl;
  im.width = camera.width();
  im.height = camera.height();
  im.tile_size = tile_size;
  im.tiles_x = (im.width + tile_size - 1) / tile_size;
  im.tiles_y = (im.height + tile_size - 1) / tile_size;

  // The affine map from screen coordinates (x/z, y/z, or x, y) to image positions.
  glm::dvec2 at0 = camera.project_camera({0.0, 0.0, 1.0});
  glm::dvec2 at1 = camera.project_camera({1.0, 1.0, 1.0});
  im.image_origin = at0;
  im.image_scale = at1 - at0;

  // Near plane first (side planes are only valid for z > 0), then a guard band one image size
  // wide on every side that keeps projected coordinates small for the fixed-point edges.
  const double g = std::max(im.width, im.height);
  const double ox = at0.x, oy = at0.y, kx = im.image_scale.x, ky = im.image_scale.y;
  const double w = im.width, h = im.height;
  if (camera.perspective()) {
    im.clip_planes = {{0.0, 0.0, 1.0, -camera.near_plane()},
                      {kx, 0.0, ox + g, 0.0},
                      {-kx, 0.0, w + g - ox, 0.0},
                      {0.0, ky, oy + g, 0.0},
                      {0.0, -ky, h + g - oy, 0.0}};
  } else {
    // Orthographic rays start on the plane through the eye: keep z >= 0.
    im.clip_planes = {{0.0, 0.0, 1.0, 0.0},
                      {kx, 0.0, 0.0, ox + g},
                      {-kx, 0.0, 0.0, w + g - ox},
                      {0.0, ky, 0.0, oy + g},
                      {0.0, -ky, 0.0, h + g - oy}};
  }

  for (const Light& light : scene.lights) im.lights.push_back(resolve_light(light));

  std::vector<bool> mesh_seen(scene.meshes.size(), false), plane_seen(scene.planes.size(), false);
  const std::vector<bool> clips = clip_meshes(scene), shown = shown_meshes(scene);
  const bool clip_only = objects == RasterObjects::clip;
  std::vector<VertexSetup> mesh_vertices;
  // One piece per mesh triangle in the usual case: the clipped ones may grow the vector once.
  size_t expected = 2 * scene.planes.size();
  for (const MeshObject& mo : scene.meshes) expected += mo.mesh ? mo.mesh->triangles.size() : 0;
  im.triangles.reserve(expected);
  for (size_t k = 0; k < scene.order.size(); ++k) {
    const ObjectRef& ref = scene.order[k];
    if (ref.kind == ObjectKind::volume) continue;
    if (ref.kind == ObjectKind::streamlines) {
      if (ref.index < 0 || static_cast<size_t>(ref.index) >= scene.streamlines.size())
        throw Error(
            fmt::format("scene order[{}]: streamlines index {} is out of range", k, ref.index));
      const StreamlineObject& so = scene.streamlines[ref.index];
      // A CSG primitive's tubes bound a region: every crossing, whatever their opacity.
      const bool csg_primitive =
          scene.csg &&
          std::any_of(scene.csg->nodes.begin(), scene.csg->nodes.end(), [&](const CsgNode& n) {
            return n.op == CsgOp::primitive && n.object.kind == ref.kind &&
                   n.object.index == ref.index;
          });
      if (clip_only || !(so.opacity > 0.0f || csg_primitive)) continue;  // hidden ones cost 0
      auto tubes = std::make_unique<Impl::Tubes>();
      tubes->object = so;
      // Coverage not for a CSG primitive: its crossings bound a region, whole or none.
      const bool covered = tube_coverage && coverable(so) && !csg_primitive;
      tubes->geometry = tube_geometry(so, covered ? silhouette_pad(camera, so) : 0.0f);
      tubes->look = make_tube_look(tubes->object, *tubes->geometry, scene.meshes);
      tubes->look.every_crossing = csg_primitive;
      if (covered)
        enable_silhouette_aa(tubes->look, camera);
      else
        hard_tubes_through_pad(tubes->look);
      tubes->order_index = static_cast<uint32_t>(k);
      im.tubes.push_back(std::move(tubes));
      continue;
    }
    const bool is_mesh = ref.kind == ObjectKind::mesh;
    const size_t count = is_mesh ? scene.meshes.size() : scene.planes.size();
    if (ref.index < 0 || static_cast<size_t>(ref.index) >= count)
      throw Error(fmt::format("scene order[{}]: {} index {} is out of range (the scene has {})", k,
                              is_mesh ? "mesh" : "plane", ref.index, count));
    ObjectInfo info;
    info.order_index = static_cast<uint32_t>(k);
    info.shaded = !clip_only;
    const uint32_t object = static_cast<uint32_t>(im.objects.size());

    if (is_mesh) {
      mesh_seen[ref.index] = true;
      const MeshObject& mo = scene.meshes[ref.index];
      if (clip_only ? !clips[ref.index] : !shown[ref.index]) continue;
      if (!mo.mesh) throw Error(fmt::format("mesh '{}': has no mesh data", mo.name));
      const Mesh& mesh = *mo.mesh;
      const bool has_normals = !mesh.normals.empty();
      if (has_normals && mesh.normals.size() != mesh.positions.size())
        throw Error(fmt::format("mesh '{}': {} normals for {} positions", mo.name,
                                mesh.normals.size(), mesh.positions.size()));
      const bool has_colors = !mesh.colors.empty();
      if (has_colors && mesh.colors.size() != mesh.positions.size())
        throw Error(fmt::format("mesh '{}': {} colours for {} positions", mo.name,
                                mesh.colors.size(), mesh.positions.size()));
      info.material = mo.material;
      info.has_normals = has_normals;
      info.has_colors = has_colors;
      info.mesh = mo.mesh;
      info.raster_begin = static_cast<uint32_t>(im.triangles.size());
      im.objects.push_back(info);
      im.add_mesh(mo.name, object, mesh_vertices);
    } else {
      plane_seen[ref.index] = true;
      const PlaneObject& pl = scene.planes[ref.index];
      if (clip_only || !shown_plane(pl)) continue;
      if (!all_finite(pl.center) || !all_finite(pl.normal) || !all_finite(pl.up))
        throw Error(fmt::format("plane '{}': center, normal and up must be finite", pl.name));
      if (!(glm::length(pl.normal) > 0.0))
        throw Error(fmt::format("plane '{}': normal is zero", pl.name));
      if (!(pl.size.x > 0.0 && pl.size.y > 0.0) || !std::isfinite(pl.size.x) ||
          !std::isfinite(pl.size.y))
        throw Error(fmt::format("plane '{}': size [{}, {}] must be positive", pl.name, pl.size.x,
                                pl.size.y));
      if (pl.volume >= 0) {
        if (static_cast<size_t>(pl.volume) >= volumes.size())
          throw Error(fmt::format("plane '{}': volume index {} is out of range ({} volumes)",
                                  pl.name, pl.volume, volumes.size()));
        if (!(pl.window.y > 0.0))
          throw Error(
              fmt::format("plane '{}': window width {} must be positive", pl.name, pl.window.y));
        info.volume = &volumes[pl.volume];
        info.window_centre = static_cast<float>(pl.window.x);
        info.window_width = static_cast<float>(pl.window.y);
        info.colormap = pl.colormap;
        if (pl.threshold) {
          if (std::isnan(*pl.threshold))
            throw Error(fmt::format("plane '{}': threshold is not a number", pl.name));
          info.threshold = static_cast<float>(*pl.threshold);
        }
        info.symmetric = pl.symmetric;
        // A thick slab along the normal at the volume's finest pitch, as a reading view's.
        const glm::dvec3 n = glm::normalize(pl.normal);
        const SlabSampling slab = slab_sampling(pl.slab.thickness, pitch_along(*info.volume, n));
        const glm::vec3 step(n * slab.spacing);
        info.slab_samples = slab.count;
        info.slab_step = info.volume->to_index(step) - info.volume->to_index(glm::vec3(0.0f));
        info.slab_mode = pl.slab.mode;
      }
      info.is_plane = true;
      info.plane_color = pl.color;
      info.plane_opacity = pl.opacity;
      info.raster_begin = static_cast<uint32_t>(im.triangles.size());
      im.objects.push_back(info);
      // Height along `up` made perpendicular to the normal, width along height x normal, so
      // (width, height, normal) is right-handed and the triangles wind around the normal.
      glm::dvec3 n = glm::normalize(pl.normal);
      glm::dvec3 v = pl.up - glm::dot(pl.up, n) * n;
      if (!(glm::length(v) > 1e-9 * glm::length(pl.up)) || !(glm::length(pl.up) > 0.0))
        throw Error(fmt::format("plane '{}': up is zero or parallel to the normal", pl.name));
      v = glm::normalize(v);
      glm::dvec3 u = glm::cross(v, n);
      glm::dvec3 hu = 0.5 * pl.size.x * u, hv = 0.5 * pl.size.y * v;
      std::array<glm::dvec3, 4> corners = {pl.center - hu - hv, pl.center + hu - hv,
                                           pl.center + hu + hv, pl.center - hu + hv};
      std::array<glm::dvec3, 4> cam;
      for (int c = 0; c < 4; ++c) cam[c] = camera.to_camera(corners[c]);
      im.add_triangle({corners[0], corners[1], corners[2]}, {cam[0], cam[1], cam[2]}, object);
      im.add_triangle({corners[0], corners[2], corners[3]}, {cam[0], cam[2], cam[3]}, object);
    }
  }
  for (size_t i = 0; i < mesh_seen.size(); ++i)
    if (!mesh_seen[i])
      throw Error(fmt::format("mesh '{}': missing from the scene order", scene.meshes[i].name));
  for (size_t i = 0; i < plane_seen.size(); ++i)
    if (!plane_seen[i])
      throw Error(fmt::format("plane '{}': missing from the scene order", scene.planes[i].name));
  mesh_vertices = {};  // freed before the bins grow
  im.build_bins();
  impl_ = std::move(impl);
}

size_t Rasterizer::triangle_count() const {
  return impl_->triangles.size();
}

// Appends every sample's tube fragments to its row, after its triangles' (arrival order).
void Rasterizer::Impl::add_tube_fragments(const TileRect& tile, std::span<const glm::vec2> offsets,
                                          SampleFragments& out) const {
  const Impl& im = *this;
  // Several samples per pixel: each covers its share of the pixel.
  std::vector<TubeLook> scaled;
  const bool covered = std::any_of(im.tubes.begin(), im.tubes.end(),
                                   [](const auto& tubes) { return tubes->look.silhouette_aa; });
  if (covered && offsets.size() > 1)
    for (const auto& tubes : im.tubes)
      share_footprint(scaled.emplace_back(tubes->look), offsets.size());
  std::vector<uint32_t> starts;
  std::vector<Fragment> merged;
  starts.reserve(out.offsets.size());
  merged.reserve(out.fragments.size());
  size_t sample = 0;
  for (int y = tile.y0; y < tile.y1; ++y)
    for (int x = tile.x0; x < tile.x1; ++x)
      for (const glm::vec2& o : offsets) {
        starts.push_back(static_cast<uint32_t>(merged.size()));
        const std::span<const Fragment> row = out.of(sample++);
        merged.insert(merged.end(), row.begin(), row.end());
        const Ray ray = im.camera.ray(x + o.x, y + o.y);
        for (size_t k = 0; k < im.tubes.size(); ++k)
          append_tube_fragments(scaled.empty() ? im.tubes[k]->look : scaled[k], ray,
                                std::numeric_limits<float>::infinity(), im.tubes[k]->order_index,
                                im.lights, merged);
      }
  starts.push_back(static_cast<uint32_t>(merged.size()));
  out.offsets.swap(starts);
  out.fragments.swap(merged);
}

void Rasterizer::rasterize(const TileRect& tile, std::span<const glm::vec2> offsets,
                           SampleFragments& out, FragmentOrder order) const {
  const Impl& im = *impl_;
  const int ts = im.tile_size;
  if (tile.x0 < 0 || tile.y0 < 0 || tile.x0 % ts != 0 || tile.y0 % ts != 0 || tile.x0 >= im.width ||
      tile.y0 >= im.height || tile.x1 != std::min(tile.x0 + ts, im.width) ||
      tile.y1 != std::min(tile.y0 + ts, im.height))
    throw Error(
        fmt::format("rasterize: tile [{}, {}) x [{}, {}) is not a tile of the {}-pixel grid "
                    "of a {}x{} image",
                    tile.x0, tile.x1, tile.y0, tile.y1, ts, im.width, im.height));
  const size_t sample_count = offsets.size();
  if (sample_count == 0 || sample_count > kMaxSamples)
    throw Error(fmt::format("rasterize: {} samples per pixel, expected 1 to {}", sample_count,
                            kMaxSamples));
  std::array<int64_t, kMaxSamples> fx, fy;  // fixed-point sample offsets
  int64_t ox_lo = kSubpixelScale, ox_hi = 0, oy_lo = kSubpixelScale, oy_hi = 0;
  for (size_t s = 0; s < sample_count; ++s) {
    const glm::vec2& o = offsets[s];
    if (!(o.x >= 0.0f && o.x <= 1.0f && o.y >= 0.0f && o.y <= 1.0f))
      throw Error(
          fmt::format("rasterize: sample offset {} ({}, {}) is outside the pixel", s, o.x, o.y));
    FixedPoint f = snap_to_subpixel(glm::dvec2(o));
    fx[s] = f.x;
    fy[s] = f.y;
    ox_lo = std::min(ox_lo, f.x);
    ox_hi = std::max(ox_hi, f.x);
    oy_lo = std::min(oy_lo, f.y);
    oy_hi = std::max(oy_hi, f.y);
  }

  const int tw = tile.width();
  const size_t total_samples = static_cast<size_t>(tw) * tile.height() * sample_count;
  const size_t bin = static_cast<size_t>(tile.y0 / ts) * im.tiles_x + tile.x0 / ts;
  const std::span<const uint32_t> items(im.bin_items.data() + im.bin_offsets[bin],
                                        im.bin_items.data() + im.bin_offsets[bin + 1]);

  // Calls fn(sample index, triangle, offset index) for every sample the edges of a triangle
  // of this tile cover, in triangle (= scene) order.
  std::array<int64_t, kMaxSamples> d0, d1, d2;  // per-sample edge function increments
  auto for_each_covered = [&](std::span<const uint32_t> of, auto&& fn) {
    for (uint32_t item : of) {
      const RasterTriangle& rt = im.triangles[item];
      const FixedBounds bounds = bounds_of(rt);
      int64_t x0, x1, y0, y1;
      pixel_span(bounds.min_x, bounds.max_x, ox_lo, ox_hi, x0, x1);
      pixel_span(bounds.min_y, bounds.max_y, oy_lo, oy_hi, y0, y1);
      x0 = std::max<int64_t>(x0, tile.x0);
      x1 = std::min<int64_t>(x1, tile.x1 - 1);
      y0 = std::max<int64_t>(y0, tile.y0);
      y1 = std::min<int64_t>(y1, tile.y1 - 1);
      if (x0 > x1 || y0 > y1) continue;
      const FixedPoint corners[3] = {corner_of(rt, 0), corner_of(rt, 1), corner_of(rt, 2)};
      TriangleEdges e;
      if (!setup_triangle_edges(corners, e)) continue;  // never: the setup kept non-zero areas
      // E(pixel corner + offset) = E(pixel corner) + d[s], exactly, in integers.
      int64_t max0 = INT64_MIN, max1 = INT64_MIN, max2 = INT64_MIN;
      for (size_t s = 0; s < sample_count; ++s) {
        d0[s] = e.a[0] * fx[s] + e.b[0] * fy[s];
        d1[s] = e.a[1] * fx[s] + e.b[1] * fy[s];
        d2[s] = e.a[2] * fx[s] + e.b[2] * fy[s];
        max0 = std::max(max0, d0[s]);
        max1 = std::max(max1, d1[s]);
        max2 = std::max(max2, d2[s]);
      }
      for (int64_t y = y0; y <= y1; ++y)
        for (int64_t x = x0; x <= x1; ++x) {
          const int64_t px = x * kSubpixelScale, py = y * kSubpixelScale;
          const int64_t e0 = e.a[0] * px + e.b[0] * py + e.c[0];
          const int64_t e1 = e.a[1] * px + e.b[1] * py + e.c[1];
          const int64_t e2 = e.a[2] * px + e.b[2] * py + e.c[2];
          if (e0 + max0 < 0 || e1 + max1 < 0 || e2 + max2 < 0) continue;  // no sample inside
          const size_t base =
              (static_cast<size_t>(y - tile.y0) * tw + (x - tile.x0)) * sample_count;
          for (size_t s = 0; s < sample_count; ++s)
            if (((e0 + d0[s]) | (e1 + d1[s]) | (e2 + d2[s])) >= 0) fn(base + s, item, rt, x, y, s);
        }
    }
  };

  // Count (integer coverage only), prefix-sum, fill. A covered sample whose ray misses the
  // plane in front of the eye (grazing triangles) or a plane's volume leaves a hole, removed
  // afterwards, so the count pass stays cheap.
  std::vector<uint32_t>& start = out.offsets;
  std::vector<Fragment>& frags = out.fragments;
  start.assign(total_samples + 1, 0u);
  // Most of a dense mesh's triangles cover no sample: the fill pass visits only those that do.
  std::vector<uint32_t>& hits = out.hits;
  hits.clear();
  for_each_covered(
      items, [&](size_t sample, uint32_t item, const RasterTriangle&, int64_t, int64_t, size_t) {
        ++start[sample];
        if (hits.empty() || hits.back() != item) hits.push_back(item);
      });
  uint32_t running = 0;
  for (size_t s = 0; s <= total_samples; ++s) {
    uint32_t c = start[s];
    start[s] = running;
    running += c;
  }
  frags.resize(running);
  bool holes = false;
  // A mesh triangle's setup is made once per tile it covers samples of, when it first does.
  uint32_t current = UINT32_MAX;
  SourceTriangle mesh_src;
  const SourceTriangle* src_of_current = nullptr;
  for_each_covered(hits, [&](size_t sample, uint32_t item, const RasterTriangle& rt, int64_t x,
                             int64_t y, size_t s) {
    if (item != current) {
      current = item;
      const uint32_t object = im.object_of(item);
      if (im.objects[object].mesh)
        src_of_current = im.mesh_source(object, rt.source, mesh_src) ? &mesh_src : nullptr;
      else
        src_of_current = &im.sources[rt.source];
    }
    Fragment& f = frags[start[sample]++];
    if (!src_of_current || !im.make_fragment(*src_of_current, im.objects[src_of_current->object],
                                             static_cast<double>(x) + offsets[s].x,
                                             static_cast<double>(y) + offsets[s].y, f)) {
      f.object = kHole;
      holes = true;
    }
  });
  // start[s] now holds the end of sample s, i.e. the beginning of s + 1.
  for (size_t s = total_samples; s > 0; --s) start[s] = start[s - 1];
  start[0] = 0;
  if (holes) {
    uint32_t kept = 0, row_begin = 0;
    for (size_t s = 0; s < total_samples; ++s) {
      const uint32_t row_end = start[s + 1];
      for (uint32_t i = row_begin; i < row_end; ++i)
        if (frags[i].object != kHole) frags[kept++] = frags[i];
      row_begin = row_end;
      start[s + 1] = kept;
    }
    frags.resize(kept);
  }

  if (!im.tubes.empty()) im.add_tube_fragments(tile, offsets, out);

  if (order == FragmentOrder::arrival) return;
  // Stable by t: fragments arrived in triangle order, which is scene order.
  auto by_depth = [](const Fragment& a, const Fragment& b) { return a.t < b.t; };
  for (size_t s = 0; s < total_samples; ++s) {
    Fragment* first = out.fragments.data() + start[s];
    Fragment* last = out.fragments.data() + start[s + 1];
    if (last - first < 2) continue;
    if (static_cast<uint32_t>(last - first) > kInsertionSortLimit) {
      std::stable_sort(first, last, by_depth);
      continue;
    }
    for (Fragment* i = first + 1; i < last; ++i) {
      Fragment v = *i;
      Fragment* j = i;
      for (; j > first && by_depth(v, *(j - 1)); --j) *j = *(j - 1);
      *j = v;
    }
  }
}

}  // namespace imx
