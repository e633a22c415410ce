#include "core/camera_model.hpp"

#include <cmath>

#include <fmt/format.h>

#include "core/math.hpp"
#include "intermix/error.hpp"

namespace imx {

CameraModel::CameraModel(const Camera& camera, int width, int height)
    : width_(width), height_(height), perspective_(camera.projection == Projection::perspective) {
  if (width <= 0 || height <= 0)
    throw Error(fmt::format("image size {}x{} must be positive", width, height));
  if (!all_finite(camera.eye) || !all_finite(camera.target) || !all_finite(camera.up))
    throw Error("camera: eye, target and up must be finite");
  eye_ = camera.eye;
  glm::dvec3 view = camera.target - camera.eye;
  if (glm::length(view) <= 0.0) throw Error("camera: eye and target coincide");
  forward_ = glm::normalize(view);
  glm::dvec3 side = glm::cross(forward_, camera.up);
  if (glm::length(side) < 1e-9 * glm::length(camera.up) || glm::length(camera.up) == 0.0)
    throw Error("camera: up is zero or parallel to the view direction");
  right_ = glm::normalize(side);
  up_ = glm::cross(right_, forward_);
  aspect_ = static_cast<double>(width) / height;
  if (perspective_) {
    if (!(camera.fov_deg > 0.0 && camera.fov_deg < 180.0))
      throw Error(fmt::format("camera.fov_deg: {} is not in (0, 180)", camera.fov_deg));
    half_height_ = std::tan(glm::radians(camera.fov_deg) * 0.5);
  } else {
    if (!(camera.ortho_height > 0.0))
      throw Error(fmt::format("camera.ortho_height: {} must be positive", camera.ortho_height));
    half_height_ = camera.ortho_height * 0.5;
  }
  const double wide = half_height_ * aspect_;
  basis_ = {(perspective_ ? forward_ : eye_) - wide * right_ + half_height_ * up_,
            (2.0 * wide / width_) * right_, (-2.0 * half_height_ / height_) * up_};
}

glm::dvec3 CameraModel::to_camera(const glm::dvec3& world) const {
  glm::dvec3 d = world - eye_;
  return {glm::dot(d, right_), glm::dot(d, up_), glm::dot(d, forward_)};
}

glm::dvec3 CameraModel::to_world(const glm::dvec3& c) const {
  return eye_ + c.x * right_ + c.y * up_ + c.z * forward_;
}

glm::dvec2 CameraModel::project_camera(const glm::dvec3& c) const {
  double sx = c.x, sy = c.y;
  if (perspective_) {
    sx /= c.z;
    sy /= c.z;
  }
  return {(sx / (half_height_ * aspect_) + 1.0) * 0.5 * width_,
          (1.0 - sy / half_height_) * 0.5 * height_};
}

double CameraModel::depth_of(const glm::dvec3& c) const {
  return perspective_ ? glm::length(c) : c.z;
}

double CameraModel::pixel_footprint(double t) const {
  double plane_height = 2.0 * half_height_;
  return perspective_ ? plane_height * t / height_ : plane_height / height_;
}

}  // namespace imx
