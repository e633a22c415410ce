#include "annotate/colour_bar.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>

namespace imx {

std::vector<double> colour_bar_ticks(double lo, double hi) {
  const double span = hi - lo;
  if (!(span > 0.0) || !std::isfinite(span)) return {lo, hi};
  const double raw = span / 5.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10.0 * magnitude;
  for (double m : {1.0, 2.0, 5.0})
    if (m * magnitude >= raw) {
      step = m * magnitude;
      break;
    }
  std::vector<double> ticks;
  const double first = std::ceil(lo / step - 1e-9), last = std::floor(hi / step + 1e-9);
  for (double k = first; k <= last && ticks.size() < 16; k += 1.0)
    ticks.push_back(k * step + 0.0);  // + 0.0: no -0
  if (ticks.size() < 2) return {lo, hi};
  return ticks;
}

std::string tick_label(double value, double step) {
  if (std::abs(value) < std::abs(step) * 1e-6) value = 0.0;
  if (std::abs(value) >= 1e6 || !(step > 0.0)) return fmt::format("{:g}", value);
  const int decimals =
      step >= 1.0 ? 0 : std::clamp(static_cast<int>(std::ceil(-std::log10(step) - 1e-9)), 0, 9);
  return fmt::format("{:.{}f}", value, decimals);
}

int colour_bar_text_size(int height) {
  return std::clamp(static_cast<int>(std::lround(height / 36.0)), 10, 28);
}

namespace {

// Premultiplied "over" of an opaque or translucent colour onto one pixel.
void blend(Image& image, int x, int y, const glm::vec4& premultiplied) {
  if (x < 0 || y < 0 || x >= image.width() || y >= image.height()) return;
  glm::vec4& dst = image.at(x, y);
  dst = premultiplied + (1.0f - premultiplied.a) * dst;
}

// The same bar twice (three planes through one map): same text, range and colours.
bool same_bar(const ColourBar& a, const ColourBar& b) {
  if (a.name != b.name || a.units != b.units || a.lo != b.lo || a.hi != b.hi) return false;
  for (int i = 0; i <= 64; ++i) {
    const double v = a.lo + (a.hi - a.lo) * i / 64.0;
    if (a.colour(v) != b.colour(v)) return false;
  }
  return true;
}

constexpr glm::vec3 kTextColour{1.0f};
constexpr float kPanelOpacity = 0.6f;

}  // namespace

std::vector<ColourBar> distinct_colour_bars(std::span<const ColourBar> bars) {
  std::vector<ColourBar> unique;
  for (const ColourBar& bar : bars) {
    if (!bar.colour || !(bar.lo < bar.hi) || !std::isfinite(bar.hi - bar.lo)) continue;
    auto same = std::find_if(unique.begin(), unique.end(),
                             [&](const ColourBar& u) { return same_bar(u, bar); });
    if (same == unique.end())
      unique.push_back(bar);
    else if (!bar.shown_by.empty())
      same->shown_by += (same->shown_by.empty() ? "" : ", ") + bar.shown_by;
  }
  return unique;
}

std::string colour_bar_title(const ColourBar& bar) {
  std::string title = bar.name;
  if (!bar.units.empty()) title += fmt::format(" ({})", bar.units);
  if (!bar.shown_by.empty()) title += " on " + bar.shown_by;
  return title;
}

std::optional<ColourBarPosition> find_colour_bar_position(std::string_view name) {
  for (ColourBarPosition p : kColourBarPositions)
    if (name == colour_bar_position_name(p)) return p;
  return std::nullopt;
}

const char* colour_bar_position_name(ColourBarPosition position) {
  switch (position) {
    case ColourBarPosition::top_right:
      return "top-right";
    case ColourBarPosition::top_left:
      return "top-left";
    case ColourBarPosition::bottom_right:
      return "bottom-right";
    case ColourBarPosition::bottom_left:
      return "bottom-left";
    case ColourBarPosition::outside:
      return "outside";
  }
  return "top-right";
}

std::vector<std::string> colour_bar_position_names() {
  std::vector<std::string> names;
  for (ColourBarPosition p : kColourBarPositions) names.emplace_back(colour_bar_position_name(p));
  return names;
}

namespace {

// One bar's text, laid out before anything is drawn so that the bars can be placed as a group.
struct BarText {
  const ColourBar* bar;
  TextBitmap title;
  std::vector<double> ticks;
  std::vector<TextBitmap> labels;
  int width = 0, height = 0;
};

}  // namespace

std::vector<ColourBarPlacement> draw_colour_bars(Image& image, std::span<const ColourBar> bars,
                                                 const TextRaster& text,
                                                 const ColourBarStyle& style) {
  const std::vector<ColourBar> unique = distinct_colour_bars(bars);
  const int f = text.pixel_height();
  const int pad = std::max(3, f / 2), strip_w = f, tick_len = std::max(3, f / 3);
  const int line = text.line_height();
  const int strip_h = std::max(3 * f, static_cast<int>(0.4 * image.height()));
  const bool outside = style.position == ColourBarPosition::outside;
  std::vector<BarText> fitting;
  int total_width = pad;
  for (const ColourBar& bar : unique) {
    BarText t{&bar, text.render(colour_bar_title(bar)), colour_bar_ticks(bar.lo, bar.hi), {}};
    const double step = t.ticks.size() > 2 ? t.ticks[1] - t.ticks[0] : bar.hi - bar.lo;
    int label_w = 0;
    for (double v : t.ticks) {
      t.labels.push_back(text.render(tick_label(v, step)));
      label_w = std::max(label_w, t.labels.back().width);
    }
    t.width = 2 * pad + std::max(t.title.width, strip_w + tick_len + 2 + label_w);
    t.height = 3 * pad + t.title.height + line + strip_h;
    if (pad + t.height > image.height()) break;
    if (!outside && total_width + t.width + pad > image.width()) break;
    total_width += t.width + pad;
    fitting.push_back(std::move(t));
  }
  if (fitting.empty()) return {};

  glm::vec3 text_colour = kTextColour;
  if (outside) {  // the canvas grows; the bars stand on the background
    Image wider(image.width() + total_width, image.height(), glm::vec4(style.background, 1.0f));
    for (int y = 0; y < image.height(); ++y)
      std::copy_n(&image.at(0, y), image.width(), &wider.at(0, y));
    const float luminance = glm::dot(style.background, glm::vec3(0.2126f, 0.7152f, 0.0722f));
    text_colour = glm::vec3(luminance > 0.2f ? 0.0f : 1.0f);
    image = std::move(wider);
  }
  const bool from_left = outside || style.position == ColourBarPosition::top_left ||
                         style.position == ColourBarPosition::bottom_left;
  const bool at_bottom = style.position == ColourBarPosition::bottom_right ||
                         style.position == ColourBarPosition::bottom_left;
  int x_edge = outside ? image.width() - total_width + pad : from_left ? pad : image.width() - pad;
  std::vector<ColourBarPlacement> placed;
  for (const BarText& t : fitting) {
    const int left = from_left ? x_edge : x_edge - t.width;
    x_edge = from_left ? left + t.width + pad : left - pad;
    const int top = at_bottom ? image.height() - pad - t.height : pad;
    if (!outside)
      for (int y = top; y < top + t.height; ++y)
        for (int x = left; x < left + t.width; ++x)
          blend(image, x, y, {0.0f, 0.0f, 0.0f, kPanelOpacity});
    draw_text(image, t.title, left + pad, top + pad, text_colour);

    ColourBarPlacement p;
    p.x0 = left + pad;
    p.x1 = p.x0 + strip_w;
    p.y0 = top + 2 * pad + t.title.height + line / 2;
    p.y1 = p.y0 + strip_h;
    p.lo = t.bar->lo;
    p.hi = t.bar->hi;
    for (int y = p.y0; y < p.y1; ++y) {
      const glm::vec4 c = t.bar->colour(p.value_at_row(y));
      for (int x = p.x0; x < p.x1; ++x) {
        // Where the object shows nothing: a checkerboard, as image editors draw transparency.
        const float grey = ((x - p.x0) / 4 + (y - p.y0) / 4) % 2 == 0 ? 0.05f : 0.2f;
        image.at(x, y) =
            c.a > 0.0f ? glm::vec4(glm::vec3(c), 1.0f) : glm::vec4(glm::vec3(grey), 1.0f);
      }
    }
    for (size_t i = 0; i < t.ticks.size(); ++i) {
      const double fraction = (t.bar->hi - t.ticks[i]) / (t.bar->hi - t.bar->lo);
      const int ty = std::clamp(p.y0 + static_cast<int>(fraction * strip_h), p.y0, p.y1 - 1);
      for (int x = p.x1; x < p.x1 + tick_len; ++x)
        blend(image, x, ty, glm::vec4(text_colour, 1.0f));
      const TextBitmap& label = t.labels[i];
      const int lx = p.x1 + tick_len + 2, ly = ty - label.height / 2;
      draw_text(image, label, lx, ly, text_colour);
      p.ticks.push_back({t.ticks[i], lx, ly, lx + label.width, ly + label.height});
    }
    placed.push_back(std::move(p));
  }
  return placed;
}

std::vector<ColourBarPlacement> draw_colour_bars(Image& image, std::span<const ColourBar> bars,
                                                 const ColourBarStyle& style) {
  if (bars.empty()) return {};
  const int size =
      static_cast<int>(std::lround(colour_bar_text_size(image.height()) * style.scale));
  const TextRaster text(find_font(), std::clamp(size, 6, 96));
  return draw_colour_bars(image, bars, text, style);
}

}  // namespace imx
