#include "io/volume/nrrd_dwmri.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <string_view>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "intermix/error.hpp"
#include "io/streams/header_text.hpp"

namespace imx::detail {

namespace {

// A finite number, as the DWMRI keys need.
std::optional<double> number(std::string_view s) {
  const std::optional<double> v = parse_header_number<double>(s);
  return v && std::isfinite(*v) ? v : std::nullopt;
}

const std::string* find_key(const std::map<std::string, std::string>& keys,
                            const std::string& key) {
  auto it = keys.find(key);
  return it == keys.end() ? nullptr : &it->second;
}

}  // namespace

std::vector<FrameLabel> dwmri_frame_labels(const std::map<std::string, std::string>& keys,
                                           int frames, const std::string& what) {
  const std::string* modality = find_key(keys, "modality");
  if (!modality || trim(*modality) != "DWMRI") return {};
  auto bad = [&](const std::string& key, const std::string& value, const std::string& why) {
    return Error(fmt::format("{}: key '{}' value '{}' {}", what, key, shown(value), why));
  };

  const std::string* b_text = find_key(keys, "DWMRI_b-value");
  if (!b_text) throw Error(fmt::format("{}: 'modality:=DWMRI' without key 'DWMRI_b-value'", what));
  const std::optional<double> b = number(*b_text);
  if (!b || *b < 0.0) throw bad("DWMRI_b-value", *b_text, "is not a b-value (a number >= 0)");

  std::vector<std::optional<glm::dvec3>> gradients(static_cast<size_t>(frames));
  for (int i = 0; i < frames;) {
    const std::string key = fmt::format("DWMRI_gradient_{:04d}", i);
    const std::string* text = find_key(keys, key);
    if (!text) {
      if (find_key(keys, fmt::format("DWMRI_B-matrix_{:04d}", i)))
        throw Error(
            fmt::format("{}: DWMRI given as B-matrices (key 'DWMRI_B-matrix_{:04d}'); "
                        "only gradients (DWMRI_gradient_NNNN) are read",
                        what, i));
      throw Error(fmt::format("{}: 'modality:=DWMRI' but no key '{}' for frame {} of {}", what, key,
                              i, frames));
    }
    // "x y z", blank- or comma-separated.
    std::string spaced = *text;
    std::replace(spaced.begin(), spaced.end(), ',', ' ');
    const auto words = split_words(spaced);
    glm::dvec3 g(0.0);
    if (words.size() != 3) throw bad(key, *text, "is not a gradient 'x y z'");
    for (int c = 0; c < 3; ++c) {
      const std::optional<double> v = number(words[static_cast<size_t>(c)]);
      if (!v) throw bad(key, *text, "is not a gradient 'x y z'");
      g[c] = *v;
    }
    long long repeat = 1;
    const std::string nex_key = fmt::format("DWMRI_NEX_{:04d}", i);
    if (const std::string* nex = find_key(keys, nex_key)) {
      const std::optional<double> n = number(*nex);
      if (!n || *n < 1 || *n != std::floor(*n) || *n > frames - i)
        throw bad(nex_key, *nex,
                  fmt::format("is not a repeat count from 1 to the {} frames left", frames - i));
      repeat = static_cast<long long>(*n);
    }
    for (long long r = 0; r < repeat; ++r) gradients[static_cast<size_t>(i + r)] = g;
    i += static_cast<int>(repeat);
  }
  if (find_key(keys, fmt::format("DWMRI_gradient_{:04d}", frames)))
    throw Error(
        fmt::format("{}: key 'DWMRI_gradient_{:04d}' is one more gradient than the {} "
                    "frames",
                    what, frames, frames));

  double longest = 0.0;
  for (const auto& g : gradients) longest = std::max(longest, glm::dot(*g, *g));
  std::vector<FrameLabel> labels(static_cast<size_t>(frames));
  for (size_t i = 0; i < labels.size(); ++i) {
    const glm::dvec3 g = *gradients[i];
    const double squared = glm::dot(g, g);
    FrameLabel& label = labels[i];
    label.b_value = longest > 0.0 ? *b * squared / longest : 0.0;
    // The gradient as the file gives it, in its 'measurement frame'; read_nrrd turns it into
    // the volume's i, j, k axes once the placement is known.
    label.b_vector = squared > 0.0 ? g / std::sqrt(squared) : glm::dvec3(0.0);
    label.text = describe_frame(label);
  }
  return labels;
}

}  // namespace imx::detail
