#include "eval_report.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace imx::cli {

namespace {

const MethodResult* find_method(const SceneResult& scene, const std::string& method) {
  for (const MethodResult& m : scene.methods)
    if (m.method == method) return &m;
  return nullptr;
}

// A method's time over the baseline's on the same scene; NaN where either did not render.
double time_ratio(const SceneResult& scene, const MethodResult& m, const std::string& baseline) {
  const MethodResult* base = find_method(scene, baseline);
  if (!m.ok || !base || !base->ok || !(base->ms_median > 0.0))
    return std::numeric_limits<double>::quiet_NaN();
  return m.ms_median / base->ms_median;
}

double capped(double psnr_db) {
  return std::min(psnr_db, kPsnrCapDb);
}

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// JSON has no infinities or NaN: +inf is "inf" (as `compare --json` writes it), NaN is null.
nlohmann::json number(double v) {
  if (std::isnan(v)) return nullptr;
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return v;
}

std::string dash_or(double v, const char* format) {
  if (std::isnan(v)) return "—";
  if (std::isinf(v)) return "∞";
  return fmt::format(fmt::runtime(format), v);
}

std::string html_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// Escaped, with `code` spans (the explanation is written once, as Markdown) as <code>.
std::string html_text(const std::string& markdown) {
  std::string out, escaped = html_escape(markdown);
  bool open = false;
  for (char c : escaped) {
    if (c == '`') {
      out += open ? "</code>" : "<code>";
      open = !open;
    } else {
      out += c;
    }
  }
  if (open) out += "</code>";
  return out;
}

// Table cells may not hold a bare '|' in Markdown.
std::string md_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

std::string memory_text(const MethodResult& m) {
  std::string stage = m.stage_bytes_per_pixel > 0.0
                          ? fmt::format("{:.0f} B/px", m.stage_bytes_per_pixel)
                          : std::string("—");
  std::string rss =
      m.peak_rss_delta_mib >= 0.0 ? fmt::format("{:.1f} MiB", m.peak_rss_delta_mib) : "—";
  return stage + " · " + rss;
}

std::string band_text(const SceneResult& s) {
  return s.band_objects.size() == 2
             ? fmt::format("band: {} × {}, radius {} px, {} pixels", s.band_objects[0],
                           s.band_objects[1], s.band_radius, s.band_pixels)
             : std::string("no band (the scene names no two objects)");
}

// What every column means, for both the HTML and the Markdown report.
std::string explanation(const EvalReport& r) {
  return fmt::format(
      "Every method against the `reference` of the same scene, on the float images (before PNG "
      "rounding). PSNR and SSIM as `intermix compare`; >4/255: fraction of pixels whose largest "
      "channel error exceeds 4/255; band PSNR: PSNR within the band around the intersection of "
      "two objects, as `intermix band` (a scene's two objects when it has exactly two, else a "
      "`--band A,B` pair it has). n/a: the method refuses the scene (its one-line reason). Time: "
      "median (min–max) ms per frame of {} "
      "timed frames after one warm-up frame, the methods interleaved frame by frame, the camera "
      "turned ±0.5° so nothing is reused; × {}: that time over {}'s on the same scene (summary: "
      "geometric mean). Memory: the stage buffers a method reports (B/px, zslab methods), and "
      "the peak resident memory of the warm-up frame over the process's resident memory at its "
      "start (Linux clear_refs; includes the image). Heat maps: largest channel error × {:g}, "
      "black → red → yellow → white. PSNR means count +∞ as {:g} dB. {} threads.",
      r.frames, r.baseline, r.baseline, r.heat_scale, kPsnrCapDb, r.threads);
}

}  // namespace

std::vector<MethodSummary> summarize(const EvalReport& report) {
  std::vector<std::string> order;
  for (const SceneResult& s : report.scenes)
    for (const MethodResult& m : s.methods)
      if (std::find(order.begin(), order.end(), m.method) == order.end()) order.push_back(m.method);
  std::vector<MethodSummary> out;
  for (const std::string& method : order) {
    MethodSummary sum;
    sum.method = method;
    sum.psnr_min_db = std::numeric_limits<double>::infinity();
    double psnr_total = 0.0, ssim_total = 0.0, band_total = 0.0, log_ratio = 0.0;
    int bands = 0, ratios = 0;
    std::vector<double> times;
    for (const SceneResult& s : report.scenes) {
      const MethodResult* m = find_method(s, method);
      if (!m) continue;
      if (!m->ok) {
        ++sum.not_applicable;
        continue;
      }
      ++sum.scenes;
      psnr_total += capped(m->quality.psnr_db);
      ssim_total += m->quality.ssim;
      if (m->quality.psnr_db < sum.psnr_min_db) {
        sum.psnr_min_db = m->quality.psnr_db;
        sum.psnr_min_scene = s.name;
      }
      if (std::isfinite(capped(m->band_psnr_db))) {
        band_total += capped(m->band_psnr_db);
        ++bands;
      }
      times.push_back(m->ms_median);
      double ratio = time_ratio(s, *m, report.baseline);
      if (std::isfinite(ratio) && ratio > 0.0) {
        log_ratio += std::log(ratio);
        ++ratios;
      }
    }
    if (sum.scenes > 0) {
      sum.psnr_mean_db = psnr_total / sum.scenes;
      sum.ssim_mean = ssim_total / sum.scenes;
      sum.ms_median = median(times);
    } else {
      sum.psnr_min_db = sum.psnr_mean_db = sum.ssim_mean = sum.ms_median =
          std::numeric_limits<double>::quiet_NaN();
    }
    if (bands > 0) sum.band_psnr_mean_db = band_total / bands;
    if (ratios > 0) sum.time_ratio = std::exp(log_ratio / ratios);
    out.push_back(sum);
  }
  return out;
}

nlohmann::json report_json(const EvalReport& r) {
  nlohmann::json scenes = nlohmann::json::array();
  for (const SceneResult& s : r.scenes) {
    nlohmann::json methods = nlohmann::json::array();
    for (const MethodResult& m : s.methods) {
      nlohmann::json j = {{"method", m.method}, {"status", m.ok ? "ok" : "n/a"}};
      if (!m.ok) {
        j["error"] = m.error;
      } else {
        j.update({{"spp", m.spp},
                  {"image", m.image},
                  {"heat_map", m.heat_map},
                  {"psnr_db", number(m.quality.psnr_db)},
                  {"ssim", m.quality.ssim},
                  {"max_error", m.quality.max_error},
                  {"frac_over_1", m.quality.frac_over_1},
                  {"frac_over_4", m.quality.frac_over_4},
                  {"frac_over_16", m.quality.frac_over_16},
                  {"band_psnr_db", number(m.band_psnr_db)},
                  {"ms_median", m.ms_median},
                  {"ms_min", m.ms_min},
                  {"ms_max", m.ms_max},
                  {"time_ratio", number(time_ratio(s, m, r.baseline))},
                  {"stage_bytes_per_pixel",
                   number(m.stage_bytes_per_pixel > 0.0 ? m.stage_bytes_per_pixel : std::nan(""))},
                  {"peak_rss_delta_mib",
                   number(m.peak_rss_delta_mib >= 0.0 ? m.peak_rss_delta_mib : std::nan(""))}});
      }
      methods.push_back(j);
    }
    nlohmann::json band = nullptr;
    if (s.band_objects.size() == 2)
      band = {{"objects", s.band_objects},
              {"radius", s.band_radius},
              {"pixels", s.band_pixels},
              {"mask", s.band_mask}};
    scenes.push_back(
        {{"name", s.name},
         {"file", s.file},
         {"description", s.description},
         {"width", s.width},
         {"height", s.height},
         {"reference",
          {{"spp", s.reference_spp}, {"ms", s.reference_ms}, {"image", s.reference_image}}},
         {"band", band},
         {"methods", methods}});
  }
  nlohmann::json summary = nlohmann::json::array();
  for (const MethodSummary& m : summarize(r))
    summary.push_back({{"method", m.method},
                       {"scenes", m.scenes},
                       {"not_applicable", m.not_applicable},
                       {"psnr_mean_db", number(m.psnr_mean_db)},
                       {"psnr_min_db", number(m.psnr_min_db)},
                       {"psnr_min_scene", m.psnr_min_scene},
                       {"ssim_mean", number(m.ssim_mean)},
                       {"band_psnr_mean_db", number(m.band_psnr_mean_db)},
                       {"ms_median", number(m.ms_median)},
                       {"time_ratio", number(m.time_ratio)}});
  return {{"command", r.command},       {"date", r.date},     {"seconds", r.seconds},
          {"threads", r.threads},       {"frames", r.frames}, {"baseline", r.baseline},
          {"heat_scale", r.heat_scale}, {"scenes", scenes},   {"summary", summary}};
}

std::string report_html(const EvalReport& r) {
  std::string h;
  auto add = [&h](const std::string& s) { h += s; };
  add("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
  add("<title>intermix eval</title>\n<style>\n"
      "body{font:14px/1.4 system-ui,sans-serif;margin:1.5em;background:#fafafa;color:#222}\n"
      "table{border-collapse:collapse;margin:.5em 0 1em}\n"
      "th,td{border:1px solid #ccc;padding:2px 8px;text-align:right}\n"
      "th:first-child,td:first-child{text-align:left}\n"
      "td.na{text-align:left;color:#888}\n"
      ".gallery{display:flex;flex-wrap:wrap;gap:8px}\n"
      "figure{margin:0;text-align:center;font-size:12px}\n"
      "figure img{display:block;width:192px;height:auto;image-rendering:pixelated}\n"
      "code{background:#eee;padding:1px 3px}\n"
      "</style>\n</head>\n<body>\n<h1>intermix eval</h1>\n");
  add(fmt::format("<p>Made by <code>{}</code> on {} in {:.0f} s.</p>\n", html_escape(r.command),
                  html_escape(r.date), r.seconds));
  add(fmt::format("<p>{}</p>\n", html_text(explanation(r))));

  add("<h2 id=\"summary\">Summary</h2>\n<table class=\"summary\">\n");
  add(fmt::format(
      "<tr><th>method</th><th>scenes</th><th>n/a</th><th>mean PSNR dB</th><th>worst PSNR "
      "dB</th><th>mean SSIM</th><th>mean band PSNR dB</th><th>median ms</th><th>× {}</th></tr>\n",
      html_escape(r.baseline)));
  for (const MethodSummary& m : summarize(r))
    add(fmt::format(
        "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{} ({})</td><td>{}</td><td>{}</td>"
        "<td>{}</td><td>{}</td></tr>\n",
        html_escape(m.method), m.scenes, m.not_applicable, dash_or(m.psnr_mean_db, "{:.2f}"),
        dash_or(m.psnr_min_db, "{:.2f}"), html_escape(m.psnr_min_scene),
        dash_or(m.ssim_mean, "{:.4f}"), dash_or(m.band_psnr_mean_db, "{:.2f}"),
        dash_or(m.ms_median, "{:.1f}"), dash_or(m.time_ratio, "{:.2f}")));
  add("</table>\n<p>Scenes:");
  for (const SceneResult& s : r.scenes)
    add(fmt::format(" <a href=\"#scene-{0}\">{0}</a>", html_escape(s.name)));
  add("</p>\n");

  for (const SceneResult& s : r.scenes) {
    add(fmt::format("<section id=\"scene-{0}\">\n<h2>{0}</h2>\n", html_escape(s.name)));
    if (!s.description.empty()) add(fmt::format("<p>{}</p>\n", html_escape(s.description)));
    add(fmt::format("<p><code>{}</code>, {}×{}; reference {} spp in {:.0f} ms; {}.</p>\n",
                    html_escape(s.file), s.width, s.height, s.reference_spp, s.reference_ms,
                    html_escape(band_text(s))));
    const bool band = s.band_objects.size() == 2;
    add("<table class=\"scene\">\n<tr><th>method</th><th>PSNR dB</th><th>SSIM</th>"
        "<th>&gt;4/255</th>");
    if (band) add("<th>band PSNR dB</th>");
    add(fmt::format("<th>ms / frame</th><th>× {}</th><th>memory</th></tr>\n",
                    html_escape(r.baseline)));
    for (const MethodResult& m : s.methods) {
      if (!m.ok) {
        add(fmt::format("<tr><td>{}</td><td class=\"na\" colspan=\"{}\">n/a: {}</td></tr>\n",
                        html_escape(m.method), band ? 7 : 6, html_escape(m.error)));
        continue;
      }
      add(fmt::format("<tr><td>{}</td><td>{}</td><td>{:.4f}</td><td>{:.4f}</td>",
                      html_escape(m.method), dash_or(m.quality.psnr_db, "{:.2f}"), m.quality.ssim,
                      m.quality.frac_over_4));
      if (band) add(fmt::format("<td>{}</td>", dash_or(m.band_psnr_db, "{:.2f}")));
      add(fmt::format("<td>{:.1f} ({:.1f}–{:.1f})</td><td>{}</td><td>{}</td></tr>\n", m.ms_median,
                      m.ms_min, m.ms_max, dash_or(time_ratio(s, m, r.baseline), "{:.2f}"),
                      html_escape(memory_text(m))));
    }
    add("</table>\n<div class=\"gallery\">\n");
    add(
        fmt::format("<figure><img src=\"{0}\" alt=\"{1} reference\"><figcaption>reference, {2} "
                    "spp</figcaption></figure>\n",
                    html_escape(s.reference_image), html_escape(s.name), s.reference_spp));
    if (band)
      add(fmt::format(
          "<figure><img src=\"{0}\" alt=\"{1} band\"><figcaption>band mask</figcaption></figure>\n",
          html_escape(s.band_mask), html_escape(s.name)));
    for (const MethodResult& m : s.methods) {
      if (!m.ok) continue;
      add(fmt::format(
          "<figure><img src=\"{0}\" alt=\"{2} {3}\"><img src=\"{1}\" alt=\"{2} {3} heat "
          "map\"><figcaption>{3}, {4} dB</figcaption></figure>\n",
          html_escape(m.image), html_escape(m.heat_map), html_escape(s.name), html_escape(m.method),
          dash_or(m.quality.psnr_db, "{:.2f}")));
    }
    add("</div>\n</section>\n");
  }
  add("</body>\n</html>\n");
  return h;
}

std::string report_markdown(const EvalReport& r) {
  std::string md = "# Every method against the reference\n\n";
  md += fmt::format(
      "Made by `{}` on {} in {:.0f} s; run the same command to regenerate this file (the HTML "
      "report with the images and heat maps is written beside the JSON in the `--out` "
      "folder).\n\n",
      r.command, r.date, r.seconds);
  md += explanation(r) + "\n\n## Summary\n\n";
  md += fmt::format(
      "| method | scenes | n/a | mean PSNR dB | worst PSNR dB (scene) | mean SSIM | mean band PSNR "
      "dB | median ms | × {} |\n|---|--:|--:|--:|--:|--:|--:|--:|--:|\n",
      r.baseline);
  for (const MethodSummary& m : summarize(r))
    md += fmt::format("| {} | {} | {} | {} | {} ({}) | {} | {} | {} | {} |\n", m.method, m.scenes,
                      m.not_applicable, dash_or(m.psnr_mean_db, "{:.2f}"),
                      dash_or(m.psnr_min_db, "{:.2f}"), m.psnr_min_scene,
                      dash_or(m.ssim_mean, "{:.4f}"), dash_or(m.band_psnr_mean_db, "{:.2f}"),
                      dash_or(m.ms_median, "{:.1f}"), dash_or(m.time_ratio, "{:.2f}"));
  for (const SceneResult& s : r.scenes) {
    const bool band = s.band_objects.size() == 2;
    md += fmt::format("\n## {}\n\n`{}`, {}×{}; reference {} spp in {:.0f} ms; {}.\n\n", s.name,
                      s.file, s.width, s.height, s.reference_spp, s.reference_ms, band_text(s));
    md += "| method | PSNR dB | SSIM | >4/255 |";
    if (band) md += " band PSNR dB |";
    md += fmt::format(" ms / frame | × {} | memory |\n|---|--:|--:|--:|", r.baseline);
    if (band) md += "--:|";
    md += "--:|--:|--:|\n";
    for (const MethodResult& m : s.methods) {
      if (!m.ok) {
        md += fmt::format("| {} | n/a: {} |\n", m.method, md_escape(m.error));
        continue;
      }
      md +=
          fmt::format("| {} | {} | {:.4f} | {:.4f} |", m.method,
                      dash_or(m.quality.psnr_db, "{:.2f}"), m.quality.ssim, m.quality.frac_over_4);
      if (band) md += fmt::format(" {} |", dash_or(m.band_psnr_db, "{:.2f}"));
      md += fmt::format(" {:.1f} ({:.1f}–{:.1f}) | {} | {} |\n", m.ms_median, m.ms_min, m.ms_max,
                        dash_or(time_ratio(s, m, r.baseline), "{:.2f}"), memory_text(m));
    }
  }
  return md;
}

}  // namespace imx::cli
