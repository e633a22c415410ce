// Parser for an object's "transform": a 4x4 matrix, translate / rotate / scale, or a file a
// registration tool wrote (registration/transform_file.hpp).
#include <cmath>
#include <memory>
#include <optional>
#include <system_error>

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "core/math.hpp"
#include "registration/displacement_field.hpp"
#include "registration/transform_file.hpp"
#include "scene/scene_parsers.hpp"
#include "scene/world_space.hpp"

namespace imx::scene_json {
namespace {

glm::dmat4 parse_matrix(const JsonReader& r) {
  if (!r.json().is_array() || r.json().size() != 4)
    r.fail("expected 4 rows of 4 numbers (row-major), got " + r.describe());
  glm::dmat4 m(1.0);
  for (size_t row = 0; row < 4; ++row) {
    std::vector<double> v = r.at(row).numbers(4);
    for (int col = 0; col < 4; ++col) m[col][static_cast<int>(row)] = v[col];
  }
  if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)
    r.at(3).fail(fmt::format("the last row must be [0, 0, 0, 1] (an affine transform), got {}",
                             r.at(3).text()));
  return m;
}

glm::dmat4 parse_inline(const JsonReader& r) {
  if (auto v = r.find("matrix")) {
    if (r.has("translate") || r.has("rotate_deg") || r.has("scale"))
      r.fail("give either \"matrix\" or translate / rotate_deg / scale, not both");
    return parse_matrix(*v);
  }
  glm::dvec3 translate(0.0), rotate(0.0), scale(1.0);
  if (auto v = r.find("translate")) translate = v->vec3(Range::coordinate());
  if (auto v = r.find("rotate_deg")) rotate = v->vec3();
  if (auto v = r.find("scale")) {
    if (v->json().is_number())
      scale = glm::dvec3(v->number());
    else if (v->json().is_array())
      scale = v->vec3();
    else
      v->fail("expected a number or an array of 3 numbers, got " + v->describe());
  }
  const glm::dvec3 x(1.0, 0.0, 0.0), y(0.0, 1.0, 0.0), z(0.0, 0.0, 1.0);
  return glm::translate(glm::dmat4(1.0), translate) *
         glm::rotate(glm::dmat4(1.0), glm::radians(rotate.z), z) *
         glm::rotate(glm::dmat4(1.0), glm::radians(rotate.y), y) *
         glm::rotate(glm::dmat4(1.0), glm::radians(rotate.x), x) *
         glm::scale(glm::dmat4(1.0), scale);
}

// {"file", "invert", "moving", "reference"}: the file's placement of its moving image.
glm::dmat4 parse_file(const JsonReader& r, SceneContext& context) {
  for (const char* inline_key : {"matrix", "translate", "rotate_deg", "scale"})
    if (r.has(inline_key))
      r.get(inline_key).fail("give either \"file\" or an inline transform, not both");
  const JsonReader file = r.get("file");
  TransformFileImages images;
  if (auto v = r.find("moving")) images.moving = context.resolve_file(*v);
  if (auto v = r.find("reference")) images.reference = context.resolve_file(*v);
  const bool invert = r.has("invert") && r.get("invert").boolean();
  const std::filesystem::path path = context.resolve_file(file);
  if (is_displacement_field(path))
    file.fail(
        fmt::format("{} is a displacement field: it warps volumes only (a mesh or an inline "
                    "transform cannot take it)",
                    path.filename().string()));
  const FileTransform read =
      file.reading(path.string(), [&] { return read_transform_file(path, images); });
  const bool stored_inverse = read.format == TransformFormat::itk_text ||
                              read.format == TransformFormat::itk_matlab ||
                              read.format == TransformFormat::afni_aff12;
  context.notes.push_back(fmt::format(
      "{}: {} is an {}, stored {}; {}", r.path(), path.filename().string(),
      transform_format_name(read.format),
      stored_inverse ? "fixed to moving (its inverse places the moving image)" : "moving to fixed",
      invert ? "\"invert\": the object is placed as the registration's fixed image"
             : "the object is placed as the registration's moving image"));
  return invert ? glm::inverse(read.moving_to_fixed) : read.moving_to_fixed;
}

// Throws unless `m` is finite, invertible, and within the scene's limits of stretch and shift.
void check_transform(const JsonReader& r, const glm::dmat4& m) {
  if (!all_finite(m)) r.fail("transform has a non-finite entry");
  // Relative to the matrix's own scale, so that micrometre and metre units both pass.
  const glm::dmat3 a(m);
  double norm = glm::length(a[0]) * glm::length(a[1]) * glm::length(a[2]);
  double det = glm::determinant(a);
  if (!(norm > 0.0) || std::abs(det) <= 1e-9 * norm)
    r.fail(fmt::format("transform is singular (determinant {})", det));
  for (int axis = 0; axis < 3; ++axis) {
    double stretch = glm::length(a[axis]);
    if (stretch < kMinScale || stretch > kMaxScale)
      r.fail(fmt::format("transform stretches axis {} by {:g}; allowed: {:g} to {:g}", "xyz"[axis],
                         stretch, kMinScale, kMaxScale));
    if (std::abs(m[3][axis]) > kMaxCoordinateMm)
      r.fail(fmt::format("transform moves {} by {:g} mm; allowed: within {:g} mm of the origin",
                         "xyz"[axis], m[3][axis], kMaxCoordinateMm));
  }
}

}  // namespace

std::optional<std::filesystem::path> displacement_field_of(const JsonReader& r,
                                                           SceneContext& context) {
  if (!r.json().is_object() || !r.has("file")) return std::nullopt;
  const std::filesystem::path path = context.resolve_file(r.get("file"));
  if (!is_displacement_field(path)) return std::nullopt;
  r.check_keys({"file"});  // no inverse of a field is computed; no images are needed
  return path;
}

std::shared_ptr<const VolumeData> warped_volume(const JsonReader& file,
                                                std::shared_ptr<const VolumeData> moving,
                                                const std::filesystem::path& field,
                                                SceneContext& context) {
  if (context.region)
    file.fail("a displacement field warps the whole volume: it cannot be rendered by region");
  std::error_code ec;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(field, ec);
  const std::string key = fmt::format("warp:{}:{}", (ec ? field : canonical).string(),
                                      static_cast<const void*>(moving.get()));
  context.used.insert(key);
  if (auto it = context.volumes.find(key); it != context.volumes.end()) return it->second;
  double seconds = 0.0;
  auto warped = file.reading(field.string(), [&] {
    return std::make_shared<const VolumeData>(warp_volume(*moving, field, &seconds));
  });
  context.notes.push_back(fmt::format(
      "{}: {} is a displacement field (fixed to moving, LPS mm): the volume was resampled "
      "through it once onto its own grid, {}x{}x{} voxels in {:.2f} s",
      file.path(), field.filename().string(), warped->dims.x, warped->dims.y, warped->dims.z,
      seconds));
  context.volumes.emplace(key, warped);
  return warped;
}

glm::dmat4 parse_transform(const JsonReader& r, SceneContext& context) {
  r.check_keys(
      {"matrix", "translate", "rotate_deg", "scale", "file", "invert", "moving", "reference"});
  glm::dmat4 m(1.0);
  if (r.has("file")) {
    m = parse_file(r, context);
  } else {
    for (const char* file_key : {"invert", "moving", "reference"})
      if (auto v = r.find(file_key))
        v->fail(fmt::format("\"{}\" applies to a transform read from a \"file\"", file_key));
    m = parse_inline(r);
    // A scene written in RAS: x and y flip on both sides (a rotation by 180 degrees about z).
    if (context.world_space == MeshSpace::ras) m = ras_lps_flip() * m * ras_lps_flip();
  }
  check_transform(r, m);
  return m;
}

}  // namespace imx::scene_json
