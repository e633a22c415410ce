#include "annotate/legend.hpp"

#include <algorithm>
#include <memory>

#include <fmt/format.h>

#include "labels/present_labels.hpp"
#include "scene/label_map_parser.hpp"

namespace imx {

std::optional<Legend> label_legend(const VolumeObject& volume) {
  if (!volume.labels || !volume.data) return std::nullopt;
  Legend legend{volume.name, {}, 0};
  for (int32_t value : present_labels(*volume.data)) {
    const LabelEntry e = scene_json::label_entry(*volume.labels, value);
    if (!e.visible || !(e.opacity > 0.0f)) continue;
    if (legend.entries.size() == kMaxLegendEntries) {
      ++legend.left_out;
      continue;
    }
    legend.entries.push_back({e.name.empty() ? fmt::format("label {}", value) : e.name, e.color});
  }
  if (legend.entries.empty()) return std::nullopt;
  return legend;
}

std::optional<Legend> streamline_legend(const StreamlineObject& object) {
  if (object.colouring != StreamlineColouring::group || !object.streamlines ||
      object.streamlines->groups.empty())
    return std::nullopt;
  Legend legend{object.name, {}, 0};
  for (const StreamlineGroup& g : object.streamlines->groups) {
    if (legend.entries.size() == kMaxLegendEntries) {
      ++legend.left_out;
      continue;
    }
    legend.entries.push_back({g.name, g.color.value_or(object.color)});
  }
  return legend;
}

std::vector<Legend> scene_legends(const Scene& scene) {
  std::vector<bool> shown_by_plane(scene.volumes.size(), false);
  for (const PlaneObject& p : scene.planes)
    if (p.opacity > 0.0f && p.volume >= 0 && static_cast<size_t>(p.volume) < scene.volumes.size())
      shown_by_plane[static_cast<size_t>(p.volume)] = true;
  std::vector<Legend> legends;
  for (const ObjectRef& ref : scene.order) {
    const auto i = static_cast<size_t>(ref.index);
    std::optional<Legend> legend;
    if (ref.kind == ObjectKind::volume) {
      const VolumeObject& v = scene.volumes.at(i);
      if (v.labels && (v.labels->shown || shown_by_plane[i])) legend = label_legend(v);
    } else if (ref.kind == ObjectKind::streamlines && scene.streamlines.at(i).opacity > 0.0f) {
      legend = streamline_legend(scene.streamlines.at(i));
    }
    if (legend) legends.push_back(std::move(*legend));
  }
  return legends;
}

Key legend_key(const Legend& legend, const TextRaster& text, int max_height,
               LegendPlacement* placed) {
  const int f = text.pixel_height(), pad = key_padding(f), line = text.line_height();
  const auto title = std::make_shared<TextBitmap>(text.render(legend.title));
  // As many rows as fit, the last saying how many more there are when some do not.
  const int room = std::max(0, (max_height - 3 * pad - title->height) / line);
  size_t rows = std::min(legend.entries.size(), static_cast<size_t>(room));
  size_t more = legend.left_out + legend.entries.size() - rows;
  if (more > 0 && rows > 0 && rows == static_cast<size_t>(room)) {
    --rows;
    ++more;
  }
  auto names = std::make_shared<std::vector<TextBitmap>>();
  int name_w = 0;
  for (size_t i = 0; i < rows; ++i) {
    names->push_back(text.render(legend.entries[i].name));
    name_w = std::max(name_w, names->back().width);
  }
  const auto tail =
      std::make_shared<TextBitmap>(text.render(more > 0 ? fmt::format("+{} more", more) : ""));
  const int swatch = f;
  Key key;
  key.width = 2 * pad + std::max({title->width, swatch + pad + name_w, tail->width});
  const size_t lines = rows + (more > 0 ? 1 : 0);
  key.height = 3 * pad + title->height + static_cast<int>(lines) * line;
  key.draw = [=, entries = legend.entries](Image& image, int left, int top, const glm::vec3& ink) {
    LegendPlacement p;
    draw_text(image, *title, left + pad, top + pad, ink);
    int y = top + 2 * pad + title->height;
    for (size_t i = 0; i < rows; ++i, y += line) {
      const int sx = left + pad, sy = y + (line - swatch) / 2;
      for (int yy = sy; yy < sy + swatch; ++yy)
        for (int xx = sx; xx < sx + swatch; ++xx)
          blend_key_pixel(image, xx, yy, entries[i].colour, 1.0f);
      const TextBitmap& name = (*names)[i];
      const int tx = sx + swatch + pad;
      draw_text(image, name, tx, y, ink);
      p.rows.push_back({entries[i].name, sx, sy, sx + swatch, sy + swatch, tx, y, tx + name.width,
                        y + name.height});
    }
    if (more > 0) {
      draw_text(image, *tail, left + pad, y, ink);
      p.rows.push_back({fmt::format("+{} more", more), 0, 0, 0, 0, left + pad, y,
                        left + pad + tail->width, y + tail->height});
    }
    if (placed) *placed = std::move(p);
  };
  return key;
}

}  // namespace imx
