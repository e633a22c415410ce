#include "frame/csg_frame.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "csg/normalize.hpp"
#include "intermix/error.hpp"

namespace imx {
std::vector<CsgBox> primitive_boxes(const Scene& scene, std::span<const CsgPrimitive> primitives) {
  std::vector<CsgBox> boxes;
  for (const CsgPrimitive& p : primitives) {
    CsgBox box;
    auto add = [&](const glm::dvec3& q) {
      box.lo = glm::min(box.lo, q);
      box.hi = glm::max(box.hi, q);
    };
    if (p.object.kind == ObjectKind::mesh) {
      for (const glm::vec3& q : scene.meshes[p.object.index].mesh->positions) add(q);
    } else if (p.object.kind == ObjectKind::streamlines) {
      // Every point, grown by the radius: a bound of the tubes whatever the selection draws.
      const StreamlineObject& o = scene.streamlines[p.object.index];
      if (o.streamlines)
        for (const glm::vec3& q : o.streamlines->points) {
          add(glm::dvec3(q) - o.radius);
          add(glm::dvec3(q) + o.radius);
        }
    } else {
      // Clip planes only shrink a volume's region: the hull's box stays a bound.
      const VolumeObject& v = scene.volumes[p.object.index];
      const glm::dvec3 last = glm::dvec3(v.data->dims) - 1.0;
      for (int c = 0; c < 8; ++c) {
        glm::dvec3 idx(c & 1 ? last.x : 0.0, c & 2 ? last.y : 0.0, c & 4 ? last.z : 0.0);
        add(glm::dvec3(v.index_to_world * glm::dvec4(idx, 1.0)));
      }
    }
    boxes.push_back(box);
  }
  return boxes;
}

CsgFrame::CsgFrame(const Scene& scene, const FrameSetup& frame, bool with_states) {
  primitive_of_object_.assign(scene.order.size(), -1);
  primitive_of_volume_.assign(frame.volumes.size(), -1);
  if (!scene.csg) return;  // no primitives: every object renders as it would without CSG
  // Clip geometry and a csg block do not combine yet: what a clip mesh does to a CSG volume's
  // presence is undecided, and the expression can hold the clip itself.
  for (const VolumeObject& v : scene.volumes)
    if (!v.clip_meshes.empty())
      throw Error(fmt::format(
          "volume '{}' has clip meshes and the scene has a csg block, which do not combine; "
          "express the clip in the csg block (e.g. a difference with the mesh), or --set "
          "objects.{}.clip=[]",
          v.name, v.name));
  const CsgExpr expr = compile_expression(*scene.csg, primitives_);
  program_ = compile_program(expr);

  const int n = static_cast<int>(primitives_.size());
  volume_of_primitive_.assign(n, -1);
  medium_.assign(n, CsgMedium{});
  for (int k = 0; k < n; ++k) {
    const CsgPrimitive& p = primitives_[k];
    const PrimitiveMask bit = PrimitiveMask{1} << k;
    for (size_t i = 0; i < scene.order.size(); ++i)
      if (scene.order[i].kind == p.object.kind && scene.order[i].index == p.object.index)
        primitive_of_object_[i] = static_cast<int8_t>(k);
    if (p.object.kind == ObjectKind::volume) {
      primitive_of_volume_[p.object.index] = static_cast<int8_t>(k);
      volume_of_primitive_[k] = static_cast<int8_t>(p.object.index);
    } else if (p.object.kind == ObjectKind::streamlines) {
      meshes_ |= bit;  // a region bounded by its fragments, as a mesh's: entries and exits
    } else {
      meshes_ |= bit;
      if (const auto& m = scene.meshes[p.object.index].interior; m && m->opacity > 0.0f) {
        medium_[k] = {m->color, m->opacity, static_cast<float>(m->unit_distance)};
        with_medium_ |= bit;
      }
    }
    if (p.presence == CsgPresence::region) geometric_ |= bit;
  }
  presence_threshold_ = static_cast<float>(scene.render.csg_presence_threshold);
  if (!with_states) return;

  NormalizeLimits limits;
  limits.max_products = scene.render.csg_max_states;
  const std::vector<CsgProduct> products = normalize(expr, limits);
  const std::vector<CsgBox> boxes = primitive_boxes(scene, primitives_);
  table_ = build_table(products, n, geometric_, parse_csg_simplify(scene.render.csg_simplify),
                       boxes, scene.render.csg_max_states, &report_);
  if (table_.states.empty()) {
    std::string names;
    for (const CsgPrimitive& p : primitives_)
      names += (names.empty() ? "" : ", ") + object_name(scene, p.object);
    throw Error(fmt::format(
        "csg: the expression is empty for this scene: no point within the bounds of its "
        "primitives ({}) satisfies it",
        names));
  }
}

CsgView CsgFrame::view() const {
  CsgView v;
  v.program = program_.code;
  v.states = table_.states;
  v.primitive_of_object = primitive_of_object_;
  v.primitive_of_volume = primitive_of_volume_;
  v.volume_of_primitive = volume_of_primitive_;
  v.medium = medium_;
  v.geometric = geometric_;
  v.meshes = meshes_;
  v.used = low_primitives(static_cast<int>(primitives_.size()));
  v.with_medium = with_medium_;
  v.presence_threshold = presence_threshold_;
  v.primitive_count = static_cast<int>(primitives_.size());
  return v;
}

}  // namespace imx
