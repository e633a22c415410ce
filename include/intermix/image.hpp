// Image: a width x height grid of linear, premultiplied RGBA floats, row 0 at the top.
#pragma once
#include <cstddef>
#include <vector>

#include <glm/vec4.hpp>

namespace imx {

class Image {
 public:
  Image() = default;
  Image(int width, int height, glm::vec4 fill = glm::vec4(0.0f))
      : width_(width), height_(height), pixels_(static_cast<size_t>(width) * height, fill) {}

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return pixels_.empty(); }
  glm::vec4& at(int x, int y) { return pixels_[static_cast<size_t>(y) * width_ + x]; }
  const glm::vec4& at(int x, int y) const { return pixels_[static_cast<size_t>(y) * width_ + x]; }
  glm::vec4* data() { return pixels_.data(); }
  const glm::vec4* data() const { return pixels_.data(); }
  size_t size() const { return pixels_.size(); }

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<glm::vec4> pixels_;
};

}  // namespace imx
