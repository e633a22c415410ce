#include "annotate/colour_bar.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "annotate/keys.hpp"

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

// The same bar twice (three planes through one map): same text, range and colours.
bool same_bar(const ColourBar& a, const ColourBar& b) {
  if (a.name != b.name || a.units != b.units || a.lo != b.lo || a.hi != b.hi) return false;
  for (int i = 0; i <= 64; ++i) {
    const double v = a.lo + (a.hi - a.lo) * i / 64.0;
    if (a.colour(v) != b.colour(v)) return false;
  }
  return true;
}

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

Key colour_bar_key(const ColourBar& bar, const TextRaster& text, int image_height,
                   ColourBarPlacement* placed) {
  const int f = text.pixel_height();
  const int pad = key_padding(f), strip_w = f, tick_len = std::max(3, f / 3);
  const int line = text.line_height();
  const int strip_h = std::max(3 * f, static_cast<int>(0.4 * image_height));
  auto title = std::make_shared<TextBitmap>(text.render(colour_bar_title(bar)));
  auto ticks = std::make_shared<std::vector<double>>(colour_bar_ticks(bar.lo, bar.hi));
  const double step = ticks->size() > 2 ? (*ticks)[1] - (*ticks)[0] : bar.hi - bar.lo;
  auto labels = std::make_shared<std::vector<TextBitmap>>();
  int label_w = 0;
  for (double v : *ticks) {
    labels->push_back(text.render(tick_label(v, step)));
    label_w = std::max(label_w, labels->back().width);
  }
  Key key;
  key.width = 2 * pad + std::max(title->width, strip_w + tick_len + 2 + label_w);
  key.height = 3 * pad + title->height + line + strip_h;
  key.draw = [=](Image& image, int left, int top, const glm::vec3& ink) {
    draw_text(image, *title, left + pad, top + pad, ink);
    ColourBarPlacement p;
    p.x0 = left + pad;
    p.x1 = p.x0 + strip_w;
    p.y0 = top + 2 * pad + title->height + line / 2;
    p.y1 = p.y0 + strip_h;
    p.lo = bar.lo;
    p.hi = bar.hi;
    for (int y = p.y0; y < p.y1; ++y) {
      const glm::vec4 c = bar.colour(p.value_at_row(y));
      for (int x = p.x0; x < p.x1; ++x) {
        // Where the object shows nothing: a checkerboard, as image editors draw transparency.
        const float grey = ((x - p.x0) / 4 + (y - p.y0) / 4) % 2 == 0 ? 0.05f : 0.2f;
        image.at(x, y) =
            c.a > 0.0f ? glm::vec4(glm::vec3(c), 1.0f) : glm::vec4(glm::vec3(grey), 1.0f);
      }
    }
    for (size_t i = 0; i < ticks->size(); ++i) {
      const double fraction = (bar.hi - (*ticks)[i]) / (bar.hi - bar.lo);
      const int ty = std::clamp(p.y0 + static_cast<int>(fraction * strip_h), p.y0, p.y1 - 1);
      for (int x = p.x1; x < p.x1 + tick_len; ++x) blend_key_pixel(image, x, ty, ink, 1.0f);
      const TextBitmap& label = (*labels)[i];
      const int lx = p.x1 + tick_len + 2, ly = ty - label.height / 2;
      draw_text(image, label, lx, ly, ink);
      p.ticks.push_back({(*ticks)[i], lx, ly, lx + label.width, ly + label.height});
    }
    if (placed) *placed = std::move(p);
  };
  return key;
}

std::vector<ColourBarPlacement> draw_colour_bars(Image& image, std::span<const ColourBar> bars,
                                                 const TextRaster& text,
                                                 const ColourBarStyle& style) {
  return draw_keys(image, bars, {}, text, style).bars;
}

std::vector<ColourBarPlacement> draw_colour_bars(Image& image, std::span<const ColourBar> bars,
                                                 const ColourBarStyle& style) {
  return draw_keys(image, bars, {}, style).bars;
}

}  // namespace imx
