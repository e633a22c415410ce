#include "methods/zslab/zslab_frame.hpp"

#include <algorithm>
#include <climits>
#include <cmath>

#include <fmt/format.h>

#include "frame/fragment_context.hpp"
#include "frame/sample_pattern.hpp"
#include "intermix/error.hpp"
#include "methods/mdvr/mdvr.hpp"
#include "methods/zslab/stage_hash.hpp"
#include "methods/zslab/zslab.hpp"
#include "scene/stage_fields.hpp"
#include "tubes/tube_coverage.hpp"
#include "tubes/tube_fragments.hpp"
#include "volume/iso_crossing.hpp"
#include "volume/projection.hpp"
#include "volume/volume_marcher.hpp"

namespace imx {

namespace {

constexpr int kIsoBisections = kZslabIsoBisections;

// The pixels outside which a mesh leaves no fragment: the projection of its world box's corners,
// two pixels wider for rounding; false (unsure: the whole image) when a corner lies at or before
// the near plane, where a projection does not bound the image of the box.
bool mesh_screen_rect(const Mesh& mesh, const CameraModel& camera, int& x0, int& y0, int& x1,
                      int& y1) {
  if (mesh.positions.empty()) return false;
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const glm::vec3& p : mesh.positions) {
    lo = glm::min(lo, glm::dvec3(p));
    hi = glm::max(hi, glm::dvec3(p));
  }
  if (!std::isfinite(lo.x + lo.y + lo.z + hi.x + hi.y + hi.z)) return false;
  glm::dvec2 a(INFINITY), b(-INFINITY);
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 w(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
    const glm::dvec3 cam = camera.to_camera(w);
    if (camera.perspective() && !(cam.z > camera.near_plane())) return false;
    const glm::dvec2 px = camera.project_camera(cam);
    a = glm::min(a, px);
    b = glm::max(b, px);
  }
  if (!std::isfinite(a.x + a.y + b.x + b.y)) return false;
  const double w = camera.width(), h = camera.height();
  x0 = static_cast<int>(std::clamp(std::floor(a.x) - 2.0, 0.0, w));
  y0 = static_cast<int>(std::clamp(std::floor(a.y) - 2.0, 0.0, h));
  x1 = static_cast<int>(std::clamp(std::ceil(b.x) + 3.0, 0.0, w));
  y1 = static_cast<int>(std::clamp(std::ceil(b.y) + 3.0, 0.0, h));
  return true;
}

// How much transparent structure a volume shows: the share of its bricks the TF keeps, times
// the transparency of its most opaque step. The volume scoring highest is cast last.
double transparent_complexity(const PreparedVolume& v, float step) {
  if (v.object->style != VolumeStyle::dvr || v.lut.max_opacity() <= 0.0f) return -1.0;
  double filled = 1.0;
  if (v.accel.occupancy && v.accel.occupancy->grid().count() > 0)
    filled = static_cast<double>(v.accel.occupancy->occupied_count()) /
             static_cast<double>(v.accel.occupancy->grid().count());
  double a = 1.0 - std::pow(1.0 - std::min(v.lut.max_opacity(), 1.0f),
                            step / std::max(v.lut.unit_distance(), 1e-6f));
  return filled * (1.0 - a + 1e-3);
}

// Position in `volume_order` (Scene::order indices) of the volume called `name`. The scene
// parser already checks the name; this catches scenes built in code.
size_t named_volume(const Scene& scene, const std::vector<size_t>& volume_order,
                    const std::string& name) {
  for (size_t i = 0; i < volume_order.size(); ++i)
    if (scene.volumes[scene.order[volume_order[i]].index].name == name) return i;
  throw Error(fmt::format("zslab: render.last_volume '{}' is not the name of a volume", name));
}

Overflow overflow_of(const RenderSettings& r) {
  if (r.overflow == "greedy") return Overflow::greedy;
  if (r.overflow == "tail") return Overflow::tail;
  throw Error(fmt::format("zslab: render.overflow is '{}', expected greedy or tail", r.overflow));
}

Sampling sampling_of(const RenderSettings& r) {
  if (r.sampling == "common") return Sampling::common;
  if (r.sampling == "per-volume") return Sampling::per_volume;
  throw Error(
      fmt::format("zslab: render.sampling is '{}', expected common or per-volume", r.sampling));
}

}  // namespace

ZslabParams zslab_params(const RenderSettings& r) {
  ZslabParams params;
  params.layers = r.layers;
  params.rt_layers = r.rt_layers;
  params.peel_layers = r.peel_layers;
  params.mix.interpolation = interpolation_of(r);
  params.mix.a_ert = static_cast<float>(r.ert_threshold);
  params.mix.overflow = overflow_of(r);
  return params;
}

ZslabFrame::ZslabFrame(const Scene& s, int spp, bool hybrid_cast, int sample_index)
    : scene(s), frame(s), offsets(frame_offsets(spp, sample_index)), hybrid(hybrid_cast) {
  const RenderSettings& r = scene.render;
  if (r.layers < 1 || r.layers > kMaxZslabLayers)
    throw Error(fmt::format("zslab: render.layers is {}, this build supports 1 to {}", r.layers,
                            kMaxZslabLayers));
  if (r.rt_layers < 1 || r.rt_layers > kMaxRtLayers)
    throw Error(fmt::format("zslab: render.rt_layers is {}, this build supports 1 to {}",
                            r.rt_layers, kMaxRtLayers));
  params = zslab_params(r);
  format = r.slab_format == "rgba8" ? SlabFormat::rgba8 : SlabFormat::rgba32f;
  footprint_at_0_ = static_cast<float>(frame.camera.pixel_footprint(0.0));
  footprint_per_mm_ = static_cast<float>(frame.camera.pixel_footprint(1.0)) - footprint_at_0_;

  // The common step (render.step_mm, else the smallest voxel pitch) as in MDVR; per-volume
  // sampling casts a coarser volume at a whole multiple of it, pre-integrated at its own step,
  // and leaves the merging of the unequal slabs to the kernel.
  steps = frame.volume_steps(frame.ray_step(r), sampling_of(r) == Sampling::per_volume);
  accelerate_for_packets(scene, frame, steps, format == SlabFormat::rgba32f);  // zslab_in_packets

  // Polygon objects and planes first, in scene order, as many per stage as fit the RT layers.
  // What does not show (hidden objects, clip meshes of opacity 0 that only cut) is in no stage.
  const bool has_volumes = !scene.volumes.empty();
  const std::vector<bool> shown = shown_meshes(scene);
  const size_t per_stage =
      static_cast<size_t>(std::max(1, r.rt_layers / std::max(1, r.peel_layers)));
  ZslabStage group;
  auto close_group = [&]() {
    if (!group.objects.empty()) {
      // The union of its meshes' screen rectangles; a plane (or a mesh not bounded) reaches
      // anywhere.
      int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
      bool bounded = true;
      for (uint32_t o : group.objects) {
        const ObjectRef& ref = scene.order[o];
        int a0, b0, a1, b1;
        if (ref.kind != ObjectKind::mesh || !scene.meshes[ref.index].mesh ||
            !mesh_screen_rect(*scene.meshes[ref.index].mesh, frame.camera, a0, b0, a1, b1)) {
          bounded = false;
          break;
        }
        x0 = std::min(x0, a0), y0 = std::min(y0, b0), x1 = std::max(x1, a1), y1 = std::max(y1, b1);
      }
      if (bounded) group.x0 = x0, group.y0 = y0, group.x1 = x1, group.y1 = y1;
      stages.push_back(std::move(group));
    }
    group = ZslabStage{};
  };
  for (size_t k = 0; k < scene.order.size(); ++k) {
    const ObjectRef& ref = scene.order[k];
    if (ref.kind == ObjectKind::volume) continue;
    if (ref.kind == ObjectKind::mesh && !shown[ref.index]) continue;
    if (ref.kind == ObjectKind::plane && !shown_plane(scene.planes[ref.index])) continue;
    if (ref.kind == ObjectKind::streamlines && !(scene.streamlines[ref.index].opacity > 0.0f))
      continue;
    std::optional<double> d = r.thickness;
    StageHash h;
    h.add(group.content).add(ref.kind);
    if (ref.kind == ObjectKind::mesh) {
      const MeshObject& m = scene.meshes[ref.index];
      if (m.thickness) d = m.thickness;
      hash_stage_fields(h, m);
      group.name += (group.name.empty() ? "" : "+") + m.name;
    } else if (ref.kind == ObjectKind::streamlines) {
      const StreamlineObject& so = scene.streamlines[ref.index];
      if (so.thickness) d = so.thickness;
      hash_stage_fields(h, scene, so);
      group.name += (group.name.empty() ? "" : "+") + so.name;
    } else {
      const PlaneObject& p = scene.planes[ref.index];
      if (p.thickness) d = p.thickness;
      hash_stage_fields(h, scene, p);
      group.name += (group.name.empty() ? "" : "+") + p.name;
    }
    // auto: the smallest voxel pitch with volumes in the scene, else the pixel footprint. Tubes:
    // 0, a surface. Their crossings are exact, and a slab as thick as a tube's chord would mix its
    // entry with its exit and with the medium and tubes in front (issue 44).
    const bool tubes = ref.kind == ObjectKind::streamlines;
    float thickness = d             ? static_cast<float>(std::max(*d, 0.0))
                      : tubes       ? 0.0f
                      : has_volumes ? static_cast<float>(frame.min_pitch)
                                    : -1.0f;
    // Tubes are ray-traced, not peeled: every crossing that can still show, not the first L.
    const bool covered = tubes && tube_coverage_on(r, true);
    const StreamlineObject* so = tubes ? &scene.streamlines[ref.index] : nullptr;
    const int peel =
        tubes ? static_cast<int>(std::min<size_t>(
                    covered ? covered_fragments_needed(*so) : tube_fragments_needed(*so), INT_MAX))
              : r.peel_layers;
    group.kind = ZslabStage::Kind::surfaces;
    group.objects.push_back(static_cast<uint32_t>(k));
    group.thickness.push_back(thickness);
    group.peel.push_back(peel);
    group.content = h.add(thickness).add(peel).add(covered).value();
    if (group.objects.size() >= std::min<size_t>(per_stage, kMaxRtLayers)) close_group();
  }
  close_group();

  // Volumes after: render.last_volume last, else the most complex transparent structure.
  std::vector<size_t> volume_order;
  for (size_t k = 0; k < scene.order.size(); ++k)
    if (scene.order[k].kind == ObjectKind::volume) volume_order.push_back(k);
  if (!r.last_volume.empty()) {
    size_t named = named_volume(scene, volume_order, r.last_volume);
    std::rotate(volume_order.begin() + static_cast<long>(named),
                volume_order.begin() + static_cast<long>(named) + 1, volume_order.end());
  } else if (!volume_order.empty()) {
    size_t best = volume_order.size() - 1;
    double best_score = -2.0;
    for (size_t i = 0; i < volume_order.size(); ++i) {
      int v = scene.order[volume_order[i]].index;
      double score = transparent_complexity(frame.volumes[v], steps[v]);
      if (score >= best_score) {
        best_score = score;
        best = i;
      }
    }
    std::rotate(volume_order.begin() + static_cast<long>(best),
                volume_order.begin() + static_cast<long>(best) + 1, volume_order.end());
  }
  for (size_t i = 0; i < volume_order.size(); ++i) {
    ZslabStage st;
    st.kind = ZslabStage::Kind::volume;
    st.objects.push_back(static_cast<uint32_t>(volume_order[i]));
    st.volume = scene.order[volume_order[i]].index;
    st.step = steps[st.volume];
    st.name = scene.volumes[st.volume].name;
    const PreparedVolume& pv = frame.volumes[st.volume];
    st.on_the_fly = hybrid && i + 1 == volume_order.size() && pv.object->style == VolumeStyle::dvr;
    StageHash h;
    hash_stage_fields(h, scene, *pv.object);
    st.content = h.add(st.step).add(st.on_the_fly).value();
    stages.push_back(std::move(st));
  }

  StageHash f;
  const Camera& c = scene.camera;
  f.add(c.eye).add(c.target).add(c.up).add(c.fov_deg).add(c.ortho_height).add(c.projection);
  f.add(scene.image.width).add(scene.image.height).add(offsets.size());
  for (const glm::vec2& o : offsets) f.add(o.x).add(o.y);  // a progressive frame's jitter
  f.add(params.layers).add(params.rt_layers).add(params.peel_layers);
  f.add(params.mix.interpolation.mode).add(params.mix.interpolation.beta).add(params.mix.a_ert);
  f.add(format).add(hybrid).add(frame.min_pitch).add(r.step_mm).add(params.mix.overflow);
  f.add(std::string_view(r.sampling));
  f.add(std::string_view(r.classification)).add(std::string_view(r.gradients));
  f.add(std::string_view(r.skipping)).add(r.brick_size);
  for (const ShadingLight& l : frame.lights) f.add(l.headlight).add(l.to_light).add(l.color);
  frame_key_ = f.value();
  rasterizers_.resize(stages.size());
}

void ZslabFrame::prepare(size_t first) {
  // The clip meshes' fragments, for the volume stages from `first` on that are clipped.
  if (!clip_rasterizer_)
    for (size_t k = first; k < stages.size(); ++k)
      if (stages[k].kind == ZslabStage::Kind::volume && frame.clip.clips(stages[k].volume)) {
        clip_rasterizer_ = std::make_shared<const Rasterizer>(scene, frame.camera, frame.volumes,
                                                              16, RasterObjects::clip);
        break;
      }
  for (size_t k = first; k < stages.size(); ++k) {
    const ZslabStage& st = stages[k];
    if (st.kind != ZslabStage::Kind::surfaces || rasterizers_[k]) continue;
    // A scene of this stage's objects only, so fragment object ids number the stage's objects.
    Scene sub;
    sub.camera = scene.camera;
    sub.image = scene.image;
    sub.volumes = scene.volumes;                                // planes sample them by index
    for (VolumeObject& v : sub.volumes) v.clip_meshes.clear();  // they name the scene's meshes
    for (uint32_t o : st.objects) {
      const ObjectRef& ref = scene.order[o];
      if (ref.kind == ObjectKind::mesh) {
        sub.order.push_back({ObjectKind::mesh, static_cast<int>(sub.meshes.size())});
        sub.meshes.push_back(scene.meshes[ref.index]);
      } else if (ref.kind == ObjectKind::streamlines) {
        sub.order.push_back({ObjectKind::streamlines, static_cast<int>(sub.streamlines.size())});
        sub.streamlines.push_back(scene.streamlines[ref.index]);
      } else {
        sub.order.push_back({ObjectKind::plane, static_cast<int>(sub.planes.size())});
        sub.planes.push_back(scene.planes[ref.index]);
      }
    }
    // A streamline object's clip meshes come along undrawn, so that its indices name them here.
    for (StreamlineObject& so : sub.streamlines)
      for (ClipMesh& c : so.clip_meshes) {
        MeshObject m = scene.meshes.at(static_cast<size_t>(c.mesh));
        m.material.opacity = 0.0f;
        m.interior.reset();
        c.mesh = static_cast<int>(sub.meshes.size());
        sub.order.push_back({ObjectKind::mesh, c.mesh});
        sub.meshes.push_back(std::move(m));
      }
    rasterizers_[k] = std::make_shared<const Rasterizer>(sub, frame.camera, frame.volumes, 16,
                                                         RasterObjects::shown,
                                                         tube_coverage_on(scene.render, true));
  }
}

void ZslabFrame::rasterize(size_t k, const TileRect& tile, SampleFragments& out) const {
  if (k < rasterizers_.size() && rasterizers_[k]) rasterizers_[k]->rasterize(tile, offsets, out);
}

bool ZslabFrame::rasterize_clip(const TileRect& tile, SampleFragments& out) const {
  if (!clip_rasterizer_) return false;
  clip_rasterizer_->rasterize(tile, offsets, out);
  return true;
}

KeptSpan ZslabFrame::kept(int volume, RayInterval span, std::span<const Fragment> clip,
                          ClipPieces& pieces) const {
  if (!frame.clip.clips(static_cast<size_t>(volume))) return KeptSpan(span);
  clip_volume(clip, frame.clip.view(), static_cast<size_t>(volume), pieces);
  return KeptSpan(span, pieces);
}

bool ZslabFrame::run_deferred(size_t k, int x, int y, const Ray& ray,
                              std::span<const Fragment> fragments, std::span<const Slab> stored,
                              SlabList& out, std::span<const Fragment> clip) const {
  return run_wide_scalar(wide_, [&] {
    const ZslabStage& st = stages[k];
    if (st.kind == ZslabStage::Kind::surfaces) {
      StageThickness th{st.thickness, footprint_at_0_, footprint_per_mm_};
      return run_surface_stage(fragments, th, stored, out, params, st.peel);
    }
    const PreparedVolume& v = frame.volumes[st.volume];
    if (!frame.may_show(st.volume, x, y)) return false;
    RayInterval span = v.intersect(ray);
    if (span.empty()) return false;
    ClipPieces pieces;
    const KeptSpan what = kept(st.volume, span, clip, pieces);
    if (what.empty()) return false;
    SlabScratch<kMaxZslabLayers> local;
    SlabList own(local.span(params.layers));
    if (v.object->style == VolumeStyle::dvr) {
      if (v.lut.max_opacity() <= 0.0f) return false;
      VolumeMarcher marcher(v, ray, what, st.step, frame.lights);
      collect_slabs(marcher, own, params.mix.a_ert, params.mix.overflow);
    } else {
      VolumeHit hit;
      bool found = v.object->style == VolumeStyle::iso
                       ? find_iso_crossing(v, ray, what, st.step, kIsoBisections, frame.lights, hit)
                       : project_volume(v, ray, what, st.step, hit);
      if (found && hit.color.a > 0.0f)
        own.push_back(virtual_slab(static_cast<float>(hit.t), st.step, hit.color));
    }
    if (own.empty()) return false;
    intermix_stage(stored, own.items(), out, params.mix);
    return true;
  });
}

glm::vec4 ZslabFrame::run_final(size_t k, int x, int y, const Ray& ray,
                                std::span<const Slab> stored,
                                std::span<const Fragment> clip) const {
  return run_wide_scalar(wide_, [&] {
    if (k < stages.size() && stages[k].on_the_fly && frame.may_show(stages[k].volume, x, y)) {
      const PreparedVolume& v = frame.volumes[stages[k].volume];
      RayInterval span = v.intersect(ray);
      ClipPieces pieces;
      const KeptSpan what = span.empty() ? KeptSpan() : kept(stages[k].volume, span, clip, pieces);
      if (!what.empty()) {
        VolumeMarcher marcher(v, ray, what, stages[k].step, frame.lights);
        return trace_hybrid(stored, marcher, params.mix);
      }
    }
    return accumulate(stored, params.mix.a_ert).color;
  });
}

}  // namespace imx
