#include "volume/tf_emptiness.hpp"

namespace imx {

TfEmptiness::TfEmptiness(const TfLut& lut)
    : lo_(lut.lo()), inv_step_(lut.inv_step()), size_(static_cast<int>(lut.entries().size())) {
  const std::vector<glm::vec4>& e = lut.entries();
  prefix_.resize(e.size() + 1);
  prefix_[0] = 0;
  for (size_t i = 0; i < e.size(); ++i) prefix_[i + 1] = prefix_[i] + (e[i].a > 0.0f ? 1 : 0);
  const int n = size_;
  next_.assign(e.size(), n);
  prev_.assign(e.size(), -1);
  for (int i = n - 1, nearest = n; i >= 0; --i) next_[i] = nearest = e[i].a > 0.0f ? i : nearest;
  for (int i = 0, nearest = -1; i < n; ++i) prev_[i] = nearest = e[i].a > 0.0f ? i : nearest;
}

}  // namespace imx
