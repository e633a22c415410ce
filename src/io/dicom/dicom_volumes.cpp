#include "io/dicom/dicom_volumes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <tuple>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "intermix/error.hpp"
#include "io/dicom/dicom_stack.hpp"

namespace imx::detail {

namespace {

// Acquisition order: InstanceNumber, then DimensionIndexValues within a multi-frame file.
bool acquired_before(const DicomFrame& a, const DicomFrame& b) {
  return std::tie(a.instance_number, a.dimension_index, a.file, a.frame) <
         std::tie(b.instance_number, b.dimension_index, b.file, b.frame);
}

// Each image's slice position as an index: images within kDuplicateMm of each other share one.
std::vector<int> position_indices(const std::vector<DicomFrame>& images, int& positions) {
  const glm::dvec3 normal = images.front().row_direction && images.front().column_direction
                                ? glm::normalize(glm::cross(*images.front().row_direction,
                                                            *images.front().column_direction))
                                : glm::dvec3(0, 0, 1);
  std::vector<size_t> order(images.size());
  std::iota(order.begin(), order.end(), size_t{0});
  auto along = [&](size_t i) {
    return glm::dot(images[i].position.value_or(glm::dvec3(0.0)), normal);
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return along(a) < along(b); });
  std::vector<int> index(images.size(), -1);
  std::vector<glm::dvec3> seen;  // one position per index
  std::vector<size_t> first_of;  // where in `order` each index starts
  for (size_t o = 0; o < order.size(); ++o) {
    const glm::dvec3 p = images[order[o]].position.value_or(glm::dvec3(0.0));
    // Same place: close in 3-D to a position of the last few along the normal.
    for (size_t s = seen.size(); s-- > 0;) {
      if (along(order[first_of[s]]) < along(order[o]) - kDuplicateMm) break;
      if (glm::length(seen[s] - p) < kDuplicateMm) {
        index[order[o]] = static_cast<int>(s);
        break;
      }
    }
    if (index[order[o]] < 0) {
      index[order[o]] = static_cast<int>(seen.size());
      seen.push_back(p);
      first_of.push_back(o);
    }
  }
  positions = static_cast<int>(seen.size());
  return index;
}

// The tags that tell volumes apart, as comparable values (NaN: absent).
using Key = std::vector<double>;

Key field_values(const DicomFrame& f, int field) {
  const double none = std::nan("");
  switch (field) {
    case 0:
      return {f.temporal_position ? double(*f.temporal_position) : none};
    case 1:
      return {f.trigger_time_ms.value_or(none)};
    case 2:
      return {f.b_value.value_or(none)};
    case 3:
      return f.gradient ? Key{f.gradient->x, f.gradient->y, f.gradient->z} : Key{none};
    case 4:
      return {f.echo_number ? double(*f.echo_number) : none};
    default:
      return {f.complex_component.empty() ? none : double(f.complex_component[0])};
  }
}
constexpr int kFields = 6;

// NaN-aware strict order on keys, so that absent values group together.
bool key_less(const Key& a, const Key& b) {
  auto rank = [](double v) { return std::isnan(v) ? std::numeric_limits<double>::infinity() : v; };
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    if (std::isnan(a[i]) != std::isnan(b[i])) return std::isnan(b[i]);
    if (rank(a[i]) != rank(b[i])) return rank(a[i]) < rank(b[i]);
  }
  return a.size() < b.size();
}
struct KeyLess {
  bool operator()(const Key& a, const Key& b) const { return key_less(a, b); }
};

struct KeyIntLess {
  bool operator()(const std::pair<Key, int>& a, const std::pair<Key, int>& b) const {
    if (key_less(a.first, b.first)) return true;
    if (key_less(b.first, a.first)) return false;
    return a.second < b.second;
  }
};

// A field separates volumes only when each of its values is found equally often at every
// position: a trigger time that is the slice timing (one value per slice) does not.
bool constant_within_volumes(const std::vector<DicomFrame>& images,
                             const std::vector<int>& position, int positions, int field) {
  std::map<Key, std::vector<int>, KeyLess> counts;
  for (size_t i = 0; i < images.size(); ++i) {
    auto& c = counts[field_values(images[i], field)];
    if (c.empty()) c.assign(static_cast<size_t>(positions), 0);
    ++c[static_cast<size_t>(position[i])];
  }
  if (counts.size() < 2) return false;  // nothing to tell apart
  return std::all_of(counts.begin(), counts.end(), [](const auto& kv) {
    return std::all_of(kv.second.begin(), kv.second.end(),
                       [&](int n) { return n == kv.second.front() && n > 0; });
  });
}

FrameLabel label_of(const std::vector<DicomFrame>& volume, double first_time, bool trigger,
                    bool echo_differs, bool component_differs) {
  FrameLabel l;
  const DicomFrame& f = volume.front();
  std::optional<double> start;
  for (const DicomFrame& g : volume)
    if (g.acquisition_time_s)
      start = std::min(start.value_or(*g.acquisition_time_s), *g.acquisition_time_s);
  if (start && std::isfinite(first_time)) l.time_s = *start - first_time;
  if (f.b_value) {
    l.b_value = *f.b_value;
    glm::dvec3 v(0.0);
    if (f.gradient && *f.b_value > 0.0 && glm::length(*f.gradient) > 1e-6 && f.row_direction &&
        f.column_direction) {
      const glm::dvec3 g = glm::normalize(*f.gradient);
      const glm::dvec3 n = glm::normalize(glm::cross(*f.row_direction, *f.column_direction));
      v = glm::dvec3(glm::dot(g, *f.row_direction), glm::dot(g, *f.column_direction),
                     glm::dot(g, n));
    }
    l.b_vector = v;
  }
  if (f.echo_time_ms && echo_differs) l.echo_time_ms = *f.echo_time_ms;
  if (trigger && f.trigger_time_ms) l.trigger_time_ms = *f.trigger_time_ms;
  if (component_differs) l.image_type = f.complex_component;
  l.text = describe_frame(l);
  return l;
}

}  // namespace

DicomVolumes split_volumes(std::vector<DicomFrame> images, const std::string& what) {
  DicomVolumes out;
  if (images.empty()) throw Error(fmt::format("{}: the series has no images", what));
  // ADC or trace images among diffusion-weighted ones are left out, as dcm2niix leaves them.
  const auto derived = std::count_if(images.begin(), images.end(),
                                     [](const DicomFrame& f) { return f.derived_diffusion; });
  if (derived > 0 && static_cast<size_t>(derived) < images.size()) {
    std::erase_if(images, [](const DicomFrame& f) { return f.derived_diffusion; });
    out.notes.push_back(fmt::format(
        "{} derived diffusion image{} (isotropic, ADC or trace) left out of the diffusion volumes",
        derived, derived == 1 ? "" : "s"));
  }
  // Without a position on every image there is no telling volumes apart: order_slices refuses
  // such a stack of several images (a series without any was placed before, as dcm2niix places
  // it).
  if (std::any_of(images.begin(), images.end(), [](const DicomFrame& f) { return !f.position; })) {
    out.volumes.push_back(std::move(images));
    return out;
  }
  int positions = 0;
  const std::vector<int> position = position_indices(images, positions);
  if (static_cast<size_t>(positions) == images.size()) {
    out.volumes.push_back(std::move(images));
    return out;
  }
  std::vector<int> per_position(static_cast<size_t>(positions), 0);
  for (int p : position) ++per_position[static_cast<size_t>(p)];
  const auto [fewest, most] = std::minmax_element(per_position.begin(), per_position.end());
  if (*fewest != *most) {
    const size_t at_few = static_cast<size_t>(fewest - per_position.begin());
    const size_t at_most = static_cast<size_t>(most - per_position.begin());
    size_t image_few = 0, image_most = 0;
    for (size_t i = 0; i < images.size(); ++i) {
      if (static_cast<size_t>(position[i]) == at_few) image_few = i;
      if (static_cast<size_t>(position[i]) == at_most) image_most = i;
    }
    throw Error(fmt::format(
        "{}: {} images at {} slice positions do not form whole volumes: {} holds {} image{} "
        "where {} holds {} (missing or extra files?)",
        what, images.size(), positions, images[image_few].file.string(), *fewest,
        *fewest == 1 ? "" : "s", images[image_most].file.string(), *most));
  }

  std::vector<bool> used(kFields);
  for (int field = 0; field < kFields; ++field)
    used[static_cast<size_t>(field)] = constant_within_volumes(images, position, positions, field);
  auto key_of = [&](const DicomFrame& f) {
    Key k;
    for (int field = 0; field < kFields; ++field)
      if (used[static_cast<size_t>(field)]) {
        Key v = field_values(f, field);
        k.insert(k.end(), v.begin(), v.end());
      }
    return k;
  };
  std::vector<size_t> order(images.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return acquired_before(images[a], images[b]); });
  // Volume of an image: its key, then its rank among the images of that key at its position.
  std::map<std::pair<Key, int>, size_t, KeyIntLess> volume_of;
  std::map<std::pair<Key, int>, int, KeyIntLess> seen_at;  // (key, position) -> images so far
  std::vector<std::vector<size_t>> members;
  for (size_t i : order) {
    const Key k = key_of(images[i]);
    const int rank = seen_at[{k, position[i]}]++;
    auto [it, fresh] = volume_of.try_emplace({k, rank}, members.size());
    if (fresh) members.emplace_back();
    members[it->second].push_back(i);
  }
  for (const std::vector<size_t>& m : members) {
    std::vector<bool> at(static_cast<size_t>(positions), false);
    for (size_t i : m) at[static_cast<size_t>(position[i])] = true;
    if (m.size() != static_cast<size_t>(positions) ||
        std::find(at.begin(), at.end(), false) != at.end())
      throw Error(fmt::format(
          "{}: the images do not form whole volumes: the volume of {} holds {} of the {} slice "
          "positions (tags that tell the volumes apart disagree)",
          what, images[m.front()].file.string(), m.size(), positions));
  }
  // Volumes come in the order of their temporal position or trigger time where those tell them
  // apart, else in the acquisition order of their first image (the order they were made in).
  std::vector<size_t> volume_order(members.size());
  std::iota(volume_order.begin(), volume_order.end(), size_t{0});
  auto timing = [&](size_t v) {
    Key k;
    for (int field : {0, 1})
      if (used[static_cast<size_t>(field)])
        k.push_back(field_values(images[members[v].front()], field)[0]);
    return k;
  };
  std::stable_sort(volume_order.begin(), volume_order.end(),
                   [&](size_t a, size_t b) { return key_less(timing(a), timing(b)); });
  double first_time = std::numeric_limits<double>::infinity();
  for (const DicomFrame& f : images)
    if (f.acquisition_time_s) first_time = std::min(first_time, *f.acquisition_time_s);
  bool echo_differs = false;
  for (const DicomFrame& f : images)
    if (f.echo_time_ms != images.front().echo_time_ms) echo_differs = true;
  for (size_t v : volume_order) {
    std::vector<DicomFrame> volume;
    for (size_t i : members[v]) volume.push_back(images[i]);
    out.labels.push_back(label_of(volume, first_time, used[1], echo_differs, used[5]));
    out.volumes.push_back(std::move(volume));
  }
  return out;
}

}  // namespace imx::detail
