// What of each scene object a kept render stage depends on: the fields the zslab stage cache
// hashes into a stage's key (methods/zslab/zslab_frame.cpp), and why the others may change
// without a new stage. Each object is taken apart by a structured binding naming every field,
// so a field added to VolumeObject, MeshObject or PlaneObject does not compile until it is
// decided here; tests/scene/stage_fields_test.cpp checks that each hashed field moves the hash.
#pragma once
#include "core/fnv1a.hpp"
#include "intermix/scene.hpp"

namespace imx {

inline void hash_stage_shading(Fnv1a& h, const Shading& s) {
  h.add(s.enabled).add(s.ambient).add(s.diffuse).add(s.specular).add(s.shininess);
}

inline void hash_stage_optional(Fnv1a& h, const std::optional<double>& v) {
  h.add(v.has_value()).add(v.value_or(0.0));
}

// A label volume's table by content (an edit of one label's colour makes a new map).
inline void hash_stage_labels(Fnv1a& h, const LabelMap* labels) {
  h.add(labels != nullptr);
  if (!labels) return;
  h.add(labels->palette_unlisted).add(labels->interpolation).add(labels->unit_distance);
  h.add(labels->shown);
  h.add(labels->entries.size());
  for (const LabelEntry& e : labels->entries)
    h.add(e.value).add(e.color).add(e.opacity).add(e.visible);  // the name is a label
}

// Data are hashed by identity: the stage cache holds the scene's data alive while it keeps a key
// (a clipped volume's stage keeps its clip meshes too).
inline void hash_stage_fields(Fnv1a& h, const Scene& scene, const VolumeObject& v) {
  const auto& [name, data, index_to_world, transfer_function, style, iso_value, xray_mode, shading,
               clip_planes, clip_meshes, display_window, window, reading_slabs, units, source_dims,
               region, frame, frames, labels] = v;
  // Not read by a render: the name and units are labels, the display window a default for
  // planes, the window the 2-D views'; the region and frame chose what `data` holds, and data is
  // hashed.
  (void)name, (void)display_window, (void)window, (void)reading_slabs, (void)units,
      (void)source_dims, (void)region, (void)frame, (void)frames;
  h.add(data.get()).add(index_to_world).add(style).add(iso_value).add(xray_mode);
  h.add(transfer_function.unit_distance).add(transfer_function.points.size());
  for (const TfPoint& p : transfer_function.points) h.add(p.value).add(p.rgba);
  hash_stage_shading(h, shading);
  h.add(clip_planes.size());
  for (const ClipPlane& c : clip_planes) h.add(c.point).add(c.normal);
  h.add(clip_meshes.size());
  for (const ClipMesh& c : clip_meshes)
    h.add(scene.meshes.at(static_cast<size_t>(c.mesh)).mesh.get()).add(c.keep_inside);
  hash_stage_labels(h, labels.get());
}

inline void hash_stage_fields(Fnv1a& h, const MeshObject& m) {
  const auto& [name, mesh, material, thickness, interior] = m;
  (void)name;  // a label
  h.add(mesh.get()).add(material.color).add(material.opacity);
  hash_stage_shading(h, material.shading);
  hash_stage_optional(h, thickness);
  h.add(interior.has_value());
  if (interior) h.add(interior->color).add(interior->opacity).add(interior->unit_distance);
}

inline void hash_stage_fields(Fnv1a& h, const Scene& scene, const StreamlineObject& o) {
  const auto& [name, streamlines, radius, colouring, color, value, colormap, range, opacity,
               group_opacity, shading, stride, min_length, regions, thickness, clip_planes,
               clip_meshes, cache, connectome, connectome_look] = o;
  (void)name, (void)cache;  // a label; the cache builds from the fields hashed here
  h.add(streamlines.get()).add(radius).add(colouring).add(color).add(value.size());
  for (char c : value) h.add(c);
  h.add(colormap).add(opacity).add(group_opacity.size()).add(stride).add(min_length);
  for (float g : group_opacity) h.add(g);
  h.add(range.has_value());
  if (range) h.add(*range);
  hash_stage_shading(h, shading);
  hash_stage_optional(h, thickness);
  h.add(clip_planes.size());
  for (const ClipPlane& c : clip_planes) h.add(c.point).add(c.normal);
  h.add(clip_meshes.size());
  for (const ClipMesh& c : clip_meshes)
    h.add(scene.meshes.at(static_cast<size_t>(c.mesh)).mesh.get()).add(c.keep_inside);
  h.add(regions.size());
  for (const StreamlineRegion& r : regions)
    h.add(r.shape)
        .add(r.avoid)
        .add(r.center)
        .add(r.radius)
        .add(r.labels.get())
        .add(r.label)
        .add(r.mesh.get());
  h.add(connectome.get());
  if (connectome) {
    const ConnectomeLook& c = connectome_look;
    h.add(c.node_scale).add(c.node_min).add(c.node_max).add(c.node_colormap);
    h.add(c.node_colormap_negative).add(c.edge_scale).add(c.edge_min).add(c.edge_max);
    h.add(c.edge_colormap).add(c.edge_colormap_negative);
  }
}

inline void hash_stage_fields(Fnv1a& h, const Scene& scene, const PlaneObject& p) {
  const auto& [name, center, normal, up, size, volume, window, color, colormap, threshold,
               symmetric, opacity, thickness, slab] = p;
  (void)name;  // a label
  h.add(center).add(normal).add(up).add(size).add(volume).add(window).add(color);
  h.add(opacity).add(colormap).add(symmetric);
  hash_stage_optional(h, threshold);
  hash_stage_optional(h, thickness);
  h.add(slab.thickness).add(slab.mode);
  if (volume >= 0 && static_cast<size_t>(volume) < scene.volumes.size()) {
    const VolumeObject& v = scene.volumes[static_cast<size_t>(volume)];
    h.add(v.data.get()).add(v.index_to_world);  // a plane reads the voxels, not the TF
    hash_stage_labels(h, v.labels.get());       // but a label volume's plane its table
  }
}

}  // namespace imx
