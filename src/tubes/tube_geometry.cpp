#include "tubes/tube_geometry.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <string>

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "tubes/connectome_primitives.hpp"
#include "tubes/tube_selection.hpp"

namespace imx {
namespace {

std::atomic<int64_t> g_embree_bytes{0};  // what Embree holds now, from its memory monitor
std::mutex g_error_mutex;
std::string g_last_error;

bool monitor(void*, ssize_t bytes, bool) {
  g_embree_bytes += bytes;
  return true;
}

void on_error(void*, RTCError, const char* message) {
  std::lock_guard lock(g_error_mutex);
  g_last_error = message ? message : "unknown error";
}

// One device for the process: its thread pool is TBB's, shared with every other parallel loop.
// The 8-wide OBB hair BVH with vertices in its leaves builds fastest (5.6 s against 7.2 s for
// the 4-wide indexed one at 8.6 M segments on 2 cores) in the same memory.
RTCDevice device() {
  static RTCDevice d = [] {
    RTCDevice made = rtcNewDevice("hair_accel=bvh8obb.virtualcurve8v");
    if (!made) throw Error("streamlines: Embree could not start (rtcNewDevice failed)");
    rtcSetDeviceErrorFunction(made, on_error, nullptr);
    rtcSetDeviceMemoryMonitorFunction(made, monitor, nullptr);
    return made;
  }();
  return d;
}

[[noreturn]] void fail(const std::string& name, const char* doing) {
  std::lock_guard lock(g_error_mutex);
  throw Error(fmt::format("streamlines '{}': {} failed: {}", name, doing, g_last_error));
}

// The K nearest hits of one ray: a sorted buffer that, once full, shrinks the ray's reach to
// its farthest entry, so traversal skips what lies behind (Embree keeps tfar of an accepted hit).
struct NearestHits {
  RTCIntersectContext context;  // first: Embree passes it back to the filter
  TubeHit* hits;
  size_t capacity;
  size_t count;
  float t_min;
  unsigned sphere_geometry;  // a connectome's spheres: their primID counts from sphere_base
  uint32_t sphere_base;
};

void keep_nearest(const RTCFilterFunctionNArguments* args) {
  NearestHits& near = *reinterpret_cast<NearestHits*>(args->context);
  const float t = RTCRayN_tfar(args->ray, args->N, 0);
  args->valid[0] = 0;
  if (!(t > near.t_min)) return;
  if (near.count == near.capacity && t >= near.hits[near.capacity - 1].t) return;
  size_t i = near.count < near.capacity ? near.count++ : near.capacity - 1;
  for (; i > 0 && near.hits[i - 1].t > t; --i) near.hits[i] = near.hits[i - 1];
  TubeHit& h = near.hits[i];
  h.t = t;
  h.normal = {RTCHitN_Ng_x(args->hit, args->N, 0), RTCHitN_Ng_y(args->hit, args->N, 0),
              RTCHitN_Ng_z(args->hit, args->N, 0)};
  h.segment =
      RTCHitN_primID(args->hit, args->N, 0) +
      (RTCHitN_geomID(args->hit, args->N, 0) == near.sphere_geometry ? near.sphere_base : 0);
  h.u = RTCHitN_u(args->hit, args->N, 0);
  if (near.count == near.capacity) {
    args->valid[0] = -1;  // accepted, with the reach set to the farthest kept hit
    RTCRayN_tfar(args->ray, args->N, 0) = near.hits[near.capacity - 1].t;
  }
}

}  // namespace

struct TubeGeometry::Embree {
  RTCScene scene = nullptr;
  ~Embree() {
    if (scene) rtcReleaseScene(scene);
  }
};

TubeGeometry::TubeGeometry(const StreamlineObject& object, float pad)
    : embree_(std::make_unique<Embree>()),
      streamlines_(object.streamlines),
      radius_(static_cast<float>(object.radius)),
      pad_(object.connectome ? 0.0f : std::max(pad, 0.0f)) {
  if (object.connectome) {
    build_connectome(object);
    return;
  }
  if (!streamlines_) throw Error(fmt::format("streamlines '{}': has no streamlines", object.name));
  const Streamlines& s = *streamlines_;
  const std::vector<uint32_t> selected = select_streamlines(object);
  selected_count_ = selected.size();
  size_t segments = 0;
  for (uint32_t i : selected) segments += s.length(i) - 1;
  const size_t points = s.points.size();
  check_memory(tube_bytes(points, segments),
               fmt::format("streamlines '{}' ({} segments)", object.name, segments));
  segment_points_.resize(segments);
  if (segments == 0) return;  // nothing drawn: no BVH
  const RTCDevice dev = device();
  RTCGeometry geometry = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
  if (!geometry) fail(object.name, "creating the tube geometry");
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), points));
  auto* flags = static_cast<uint8_t*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_FLAGS, 0, RTC_FORMAT_UCHAR, 1, segments));
  if (!vertices || !flags) {
    rtcReleaseGeometry(geometry);
    fail(object.name, "allocating the tube vertices");
  }
  const float radius = radius_ + pad_;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points, 1 << 16), [&](const auto& r) {
    for (size_t p = r.begin(); p < r.end(); ++p) {
      const glm::vec3& v = s.points[p];
      vertices[4 * p] = v.x, vertices[4 * p + 1] = v.y, vertices[4 * p + 2] = v.z;
      vertices[4 * p + 3] = radius;
    }
  });
  size_t k = 0;
  for (uint32_t i : selected) {
    const uint32_t a = s.offsets[i], b = s.offsets[i + 1];
    for (uint32_t p = a; p + 1 < b; ++p, ++k) {
      segment_points_[k] = p;
      // Joined segments: Embree leaves out the inner caps, so a bend has no seam or extra hit.
      flags[k] = static_cast<uint8_t>((p > a ? RTC_CURVE_FLAG_NEIGHBOR_LEFT : 0) |
                                      (p + 2 < b ? RTC_CURVE_FLAG_NEIGHBOR_RIGHT : 0));
    }
  }
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT,
                             segment_points_.data(), 0, sizeof(uint32_t), segments);
  rtcCommitGeometry(geometry);
  embree_->scene = rtcNewScene(dev);
  rtcSetSceneFlags(embree_->scene, RTC_SCENE_FLAG_COMPACT | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  rtcSetSceneBuildQuality(embree_->scene, RTC_BUILD_QUALITY_LOW);
  rtcAttachGeometry(embree_->scene, geometry);
  rtcReleaseGeometry(geometry);
  const int64_t before = g_embree_bytes.load();
  rtcCommitScene(embree_->scene);
  if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) fail(object.name, "building the tubes' BVH");
  bytes_ = static_cast<size_t>(std::max<int64_t>(g_embree_bytes.load() - before, 0)) + points * 16 +
           segments * 5;
}

// Tubes as 2-point round linear curves with their own vertices (the radius per tube) and caps
// at both ends; spheres as Embree's sphere points. Both in one scene, each primitive one colour.
void TubeGeometry::build_connectome(const StreamlineObject& object) {
  connectome_ = true;
  const ConnectomePrimitives shown =
      connectome_primitives(*object.connectome, object.connectome_look);
  const size_t tubes = shown.tubes.size(), spheres = shown.spheres.size();
  check_memory((tubes * 2 + spheres) * 16 + (tubes + spheres) * (4 + 1 + 12 + 64),
               fmt::format("connectome '{}' ({} tubes, {} spheres)", object.name, tubes, spheres));
  primitive_colors_.reserve(tubes + spheres);
  for (const ConnectomeTube& t : shown.tubes) primitive_colors_.push_back(t.color);
  for (const ConnectomeSphere& s : shown.spheres) primitive_colors_.push_back(s.color);
  if (tubes + spheres == 0) return;  // nothing drawn: no BVH
  const RTCDevice dev = device();
  embree_->scene = rtcNewScene(dev);
  rtcSetSceneFlags(embree_->scene, RTC_SCENE_FLAG_COMPACT | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  auto attach = [&](RTCGeometry geometry) {
    rtcCommitGeometry(geometry);
    const unsigned id = rtcAttachGeometry(embree_->scene, geometry);
    rtcReleaseGeometry(geometry);
    return id;
  };
  if (tubes > 0) {
    RTCGeometry geometry = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
    if (!geometry) fail(object.name, "creating the connectome's tubes");
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 2 * tubes));
    auto* index = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(uint32_t), tubes));
    auto* flags = static_cast<uint8_t*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_FLAGS, 0, RTC_FORMAT_UCHAR, 1, tubes));
    if (!vertices || !index || !flags) {
      rtcReleaseGeometry(geometry);
      fail(object.name, "allocating the connectome's tubes");
    }
    for (size_t i = 0; i < tubes; ++i) {
      const ConnectomeTube& t = shown.tubes[i];
      float* v = vertices + 8 * i;
      v[0] = t.a.x, v[1] = t.a.y, v[2] = t.a.z, v[3] = t.radius;
      v[4] = t.b.x, v[5] = t.b.y, v[6] = t.b.z, v[7] = t.radius;
      index[i] = static_cast<uint32_t>(2 * i);
      flags[i] = 0;  // no neighbours: each tube is a capsule of its own
    }
    attach(geometry);
  }
  if (spheres > 0) {
    RTCGeometry geometry = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    if (!geometry) fail(object.name, "creating the connectome's spheres");
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), spheres));
    if (!vertices) {
      rtcReleaseGeometry(geometry);
      fail(object.name, "allocating the connectome's spheres");
    }
    for (size_t i = 0; i < spheres; ++i) {
      const ConnectomeSphere& s = shown.spheres[i];
      float* v = vertices + 4 * i;
      v[0] = s.center.x, v[1] = s.center.y, v[2] = s.center.z, v[3] = s.radius;
    }
    sphere_geometry_ = attach(geometry);
    sphere_base_ = static_cast<uint32_t>(tubes);
  }
  const int64_t before = g_embree_bytes.load();
  rtcCommitScene(embree_->scene);
  if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) fail(object.name, "building the connectome's BVH");
  bytes_ = static_cast<size_t>(std::max<int64_t>(g_embree_bytes.load() - before, 0)) +
           (tubes * 2 + spheres) * 16 + primitive_colors_.size() * sizeof(glm::vec3);
}

TubeGeometry::~TubeGeometry() = default;

uint32_t TubeGeometry::streamline(uint32_t segment) const {
  const std::vector<uint32_t>& offsets = streamlines_->offsets;
  const uint32_t point = segment_points_[segment];
  return static_cast<uint32_t>(std::upper_bound(offsets.begin(), offsets.end(), point) -
                               offsets.begin() - 1);
}

size_t TubeGeometry::nearest_hits(const Ray& ray, float t_min, float t_max,
                                  std::span<TubeHit> out) const {
  if (out.empty() || !embree_->scene) return 0;
  NearestHits near;
  rtcInitIntersectContext(&near.context);
  near.context.filter = keep_nearest;
  near.hits = out.data();
  near.capacity = out.size();
  near.count = 0;
  near.t_min = t_min;
  near.sphere_geometry = sphere_geometry_;
  near.sphere_base = sphere_base_;
  RTCRayHit rh;
  rh.ray.org_x = ray.origin.x, rh.ray.org_y = ray.origin.y, rh.ray.org_z = ray.origin.z;
  rh.ray.dir_x = ray.dir.x, rh.ray.dir_y = ray.dir.y, rh.ray.dir_z = ray.dir.z;
  rh.ray.tnear = std::max(t_min, 0.0f);
  rh.ray.tfar = t_max;
  rh.ray.time = 0.0f;
  rh.ray.mask = ~0u;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(embree_->scene, &near.context, &rh);
  return near.count;
}

}  // namespace imx
