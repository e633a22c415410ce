// Accumulator: the running mean of a progressive frame's jittered 1-sample images, which after
// every sample index of the spp pattern is the spp image render() gives (RenderOptions).
#pragma once
#include <vector>

#include <glm/vec4.hpp>

#include "intermix/image.hpp"

namespace imx::server {

class Accumulator {
 public:
  void reset() { samples_ = 0; }

  void add(const Image& sample) {
    if (samples_ == 0 || sum_.size() != sample.size() || width_ != sample.width()) {
      width_ = sample.width();
      height_ = sample.height();
      sum_.assign(sample.data(), sample.data() + sample.size());
      samples_ = 1;
      return;
    }
    for (size_t i = 0; i < sum_.size(); ++i) sum_[i] += sample.data()[i];
    ++samples_;
  }

  int samples() const { return samples_; }

  Image mean() const {
    Image out(width_, height_);
    const float weight = 1.0f / static_cast<float>(samples_ > 0 ? samples_ : 1);
    for (size_t i = 0; i < sum_.size(); ++i) out.data()[i] = sum_[i] * weight;
    return out;
  }

 private:
  int width_ = 0, height_ = 0;
  int samples_ = 0;
  std::vector<glm::vec4> sum_;
};

}  // namespace imx::server
