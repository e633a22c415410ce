// CameraModel: turns a scene Camera and an image size into rays and projections.
#pragma once
#include <glm/glm.hpp>

#include "core/ray.hpp"
#include "intermix/scene.hpp"

namespace imx {

// Pixel coordinates: x right, y down, pixel (i, j) covers [i, i+1) x [j, j+1), centre at +0.5.
class CameraModel {
 public:
  CameraModel(const Camera& camera, int width, int height);

  // The rays as a linear map of the image position: ray(px, py) starts at `at + px * per_x +
  // py * per_y` (orthographic) or runs along its normalized value (perspective).
  struct PixelBasis {
    glm::dvec3 at, per_x, per_y;
  };
  const PixelBasis& pixel_basis() const { return basis_; }

  // The ray through image position (px, py). Perspective rays start at the eye;
  // orthographic rays start on the plane through the eye, perpendicular to the view.
  // Inline: called once per pixel (per-pixel methods, the packet tiles' partial blocks), and
  // returning the Ray through memory from an out-of-line call cost a store-forwarding stall.
  Ray ray(double px, double py) const {
    const glm::dvec3 p = basis_.at + px * basis_.per_x + py * basis_.per_y;
    return perspective_ ? Ray{glm::vec3(eye_), glm::vec3(glm::normalize(p))}
                        : Ray{glm::vec3(p), glm::vec3(forward_)};
  }

  // Camera-space coordinates of a world point: x right, y up, z forward (depth along view).
  glm::dvec3 to_camera(const glm::dvec3& world) const;
  glm::dvec3 to_world(const glm::dvec3& camera_space) const;

  // Image position of a camera-space point with z > 0 (any z for orthographic).
  glm::dvec2 project_camera(const glm::dvec3& camera_space) const;
  glm::dvec2 project(const glm::dvec3& world) const { return project_camera(to_camera(world)); }

  // Depth t (distance along the ray) of a camera-space point seen at its projection.
  double depth_of(const glm::dvec3& camera_space) const;

  // World-space width of one pixel at depth t along the central ray.
  double pixel_footprint(double t) const;

  bool perspective() const { return perspective_; }
  int width() const { return width_; }
  int height() const { return height_; }
  glm::dvec3 eye() const { return eye_; }
  glm::dvec3 forward() const { return forward_; }
  glm::dvec3 right() const { return right_; }
  glm::dvec3 up() const { return up_; }
  // Camera-space distance of the near plane used to clip geometry (perspective).
  double near_plane() const { return near_; }

 private:
  glm::dvec3 eye_, forward_, right_, up_;
  int width_, height_;
  bool perspective_;
  double half_height_;  // tan(fov/2) for perspective, ortho_height/2 for orthographic
  double aspect_;
  double near_ = 1e-3;
  PixelBasis basis_;
};

}  // namespace imx
