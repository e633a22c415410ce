// intermix eval [SCENES...] --out DIR: every method on every scene against the reference, as an
// HTML report with the images and heat maps, a JSON file and optionally Markdown tables.
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "core/parallel.hpp"
#include "eval_report.hpp"
#include "intermix/band_metrics.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/metrics.hpp"
#include "intermix/render.hpp"
#include "intermix/renderer.hpp"
#include "intermix/scene.hpp"
#include "io/streams/atomic_file.hpp"
#include "io/streams/input_file.hpp"
#include "lab_commands.hpp"
#include "probes/first_hit_depth.hpp"

namespace fs = std::filesystem;

namespace imx::cli {

namespace {

// ---- memory: peak resident set over a frame, from Linux's /proc ----------------------------

// A "VmRSS:"-style line of /proc/self/status in MiB; < 0 when absent.
double status_mib(const std::string& key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) return std::strtod(line.c_str() + key.size(), nullptr) / 1024.0;
  return -1.0;
}

// Resets the peak RSS to the current RSS (Linux >= 4.0); false where that is not possible.
bool reset_peak_rss() {
  ::malloc_trim(0);  // freed heap goes back, so the next frame's growth shows
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.flush();
  return static_cast<bool>(clear);
}

// ---- scenes ----------------------------------------------------------------------------------

std::vector<std::string> object_names(const Scene& scene) {
  std::vector<std::string> names;
  for (const ObjectRef& ref : scene.order) names.push_back(object_name(scene, ref));
  return names;
}

// The band's two objects: the first --band pair the scene has both of, else the scene's two
// objects when it has exactly two, else none.
std::vector<std::string> band_objects(const Scene& scene,
                                      const std::vector<std::vector<std::string>>& pairs) {
  std::vector<std::string> names = object_names(scene);
  auto has = [&](const std::string& n) {
    return std::find(names.begin(), names.end(), n) != names.end();
  };
  for (const auto& pair : pairs)
    if (has(pair[0]) && has(pair[1])) return pair;
  if (names.size() == 2) return names;
  return {};
}

// A folder name from a scene file's stem: letters, digits, '.', '-', '_'; unique in `taken`.
std::string folder_name(const fs::path& file, std::set<std::string>& taken) {
  std::string stem = file.stem().string(), name;
  for (char c : stem)
    name +=
        std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' ? c : '_';
  if (name.empty() || name == "." || name == "..") name = "scene";
  std::string unique = name;
  for (int i = 2; taken.count(unique); ++i) unique = fmt::format("{}-{}", name, i);
  taken.insert(unique);
  return unique;
}

std::string first_line(const std::string& text) {
  return text.substr(0, text.find('\n'));
}

// The camera turned about the target's vertical by `degrees`, so a timed frame reuses nothing.
Camera turned(const Camera& camera, double degrees) {
  glm::dmat4 turn = glm::rotate(glm::dmat4(1.0), glm::radians(degrees), camera.up);
  Camera c = camera;
  c.eye = camera.target + glm::dvec3(turn * glm::dvec4(camera.eye - camera.target, 0.0));
  return c;
}

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

double median_of(std::vector<double> ms) {
  std::sort(ms.begin(), ms.end());
  size_t n = ms.size();
  return n % 2 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2]);
}

// The command line from /proc (the program as "intermix"), arguments quoted where needed.
std::string command_line() {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::string> args;
  for (size_t start = 0; start < all.size();) {
    size_t end = all.find('\0', start);
    if (end == std::string::npos) end = all.size();
    args.push_back(all.substr(start, end - start));
    start = end + 1;
  }
  if (args.empty()) return "intermix eval";
  args[0] = "intermix";
  std::string out;
  for (const std::string& a : args) {
    bool plain = !a.empty() && a.find_first_of(" \t\"'$`\\*?[]{}()<>|&;#") == std::string::npos;
    out += (out.empty() ? "" : " ") + (plain ? a : "'" + a + "'");
  }
  return out;
}

std::string utc_now() {
  std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M UTC", &tm);
  return text;
}

void write_text_atomically(const fs::path& file, const std::string& text) {
  write_file_atomically(file, [&](std::ostream& out) { out << text; });
}

void progress(const std::string& line) {
  if (!quiet()) std::fprintf(stderr, "intermix-lab: eval %s\n", line.c_str());
}

struct Options : SceneOptions {
  std::vector<std::string> scenes, methods, bands;
  std::string out = "out/eval", markdown;
  int size = 0, ref_spp = 0, frames = 3, radius = 2;
  float band_opacity = 0.5f;
  double heat_scale = 8.0;
};

// Runs every method on one loaded scene; the images go into `dir`/`s.name`/.
void evaluate_scene(const Scene& scene, const Options& o, const std::vector<std::string>& methods,
                    const std::vector<std::vector<std::string>>& pairs, const fs::path& dir,
                    const std::string& tag, SceneResult& s) {
  const fs::path folder = dir / s.name;
  s.width = scene.image.width;
  s.height = scene.image.height;

  RenderOptions ref_options;
  ref_options.method = "reference";
  ref_options.spp = o.ref_spp;
  ref_options.threads = o.threads;
  s.reference_spp = o.ref_spp > 0          ? o.ref_spp
                    : scene.render.spp > 0 ? scene.render.spp
                                           : default_spp("reference");
  progress(fmt::format("{}: reference at {} spp", tag, s.reference_spp));
  auto start = std::chrono::steady_clock::now();
  Image reference;
  try {
    reference = render(scene, ref_options);
  } catch (const Error& e) {
    throw Error(fmt::format("{}: reference: {}", s.file, e.what()));
  }
  s.reference_ms = ms_since(start);
  s.reference_image = s.name + "/reference.png";
  write_png(reference, dir / s.reference_image);

  std::vector<uint8_t> band;
  s.band_objects = band_objects(scene, pairs);
  if (!s.band_objects.empty()) {
    band = intersection_band(first_hit_depth(scene, s.band_objects[0], o.band_opacity, o.threads),
                             first_hit_depth(scene, s.band_objects[1], o.band_opacity, o.threads),
                             o.radius);
    s.band_radius = o.radius;
    Image mask(s.width, s.height, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    for (size_t i = 0; i < band.size(); ++i) {
      s.band_pixels += band[i];
      if (band[i]) mask.data()[i] = glm::vec4(1.0f);
    }
    s.band_mask = s.name + "/band.png";
    write_png(mask, dir / s.band_mask);
  }

  // Warm-up frame of every method: its image, quality and memory. A method that refuses the
  // scene is n/a with its reason, not a failure of the evaluation.
  std::vector<RenderOptions> options(methods.size());
  for (size_t i = 0; i < methods.size(); ++i) {
    MethodResult m;
    m.method = methods[i];
    options[i].method = methods[i];
    options[i].spp = o.spp;
    options[i].threads = o.threads;
    m.spp = o.spp > 0 ? o.spp : scene.render.spp > 0 ? scene.render.spp : default_spp(m.method);
    Renderer renderer;  // a fresh one, so its stats are of this frame alone
    bool peak_known = reset_peak_rss();
    double rss_before = status_mib("VmRSS:");
    Image image;
    try {
      image = renderer.render(scene, options[i]);
      m.ok = true;
    } catch (const Error& e) {
      m.error = first_line(e.what());
    }
    double peak = status_mib("VmHWM:");
    if (!m.ok) {
      progress(fmt::format("{}: {}: n/a: {}", tag, m.method, m.error));
      s.methods.push_back(m);
      continue;
    }
    if (peak_known && peak >= 0.0 && rss_before >= 0.0)
      m.peak_rss_delta_mib = std::max(0.0, peak - rss_before);
    const RendererStats& stats = renderer.last_stats();
    m.stage_bytes_per_pixel = stats.stream_bytes_per_pixel + stats.kept_bytes_per_pixel;
    m.quality = compare_images(reference, image);
    if (!band.empty()) m.band_psnr_db = masked_psnr(reference, image, band);
    m.image = s.name + "/" + m.method + ".png";
    m.heat_map = s.name + "/" + m.method + "-heat.png";
    write_png(image, dir / m.image);
    write_png(error_heat_map(reference, image, o.heat_scale), dir / m.heat_map);
    progress(fmt::format("{}: {}: PSNR {:.2f} dB, SSIM {:.4f}", tag, m.method, m.quality.psnr_db,
                         m.quality.ssim));
    s.methods.push_back(m);
  }

  // Timed frames in rounds over the methods, so a machine that changes speed during the run
  // weighs on every method alike.
  std::vector<std::vector<double>> times(methods.size());
  for (int f = 0; f < o.frames; ++f) {
    Scene frame = scene;
    frame.camera = turned(scene.camera, f % 2 == 0 ? 0.5 : -0.5);
    for (size_t i = 0; i < methods.size(); ++i) {
      if (!s.methods[i].ok) continue;
      auto t0 = std::chrono::steady_clock::now();
      try {
        render(frame, options[i]);
      } catch (const Error& e) {
        throw Error(fmt::format("{}: {} (timed frame): {}", s.file, methods[i], e.what()));
      }
      times[i].push_back(ms_since(t0));
    }
  }
  for (size_t i = 0; i < methods.size(); ++i) {
    if (times[i].empty()) continue;
    s.methods[i].ms_median = median_of(times[i]);
    s.methods[i].ms_min = *std::min_element(times[i].begin(), times[i].end());
    s.methods[i].ms_max = *std::max_element(times[i].begin(), times[i].end());
  }
  progress(fmt::format("{}: timed {} frames per method", tag, o.frames));
}

}  // namespace

Command add_eval(CLI::App& app) {
  auto o = std::make_shared<Options>();
  app.add_option("scenes", o->scenes, "scene files (default: examples/*.json in this folder)");
  app.add_option("--out", o->out,
                 "report folder: index.html, eval.json, images (default out/eval)");
  app.add_option("--markdown", o->markdown, "also write the tables as Markdown to this file");
  app.add_option("--method", o->methods,
                 "method to evaluate (repeatable; default: every method but the reference)");
  app.add_option("--ref-spp", o->ref_spp,
                 "reference samples per pixel (default: the scene's, else the reference's 16)")
      ->check(in_range(1, kMaxSpp));
  app.add_option("--spp", o->spp, "the methods' samples per pixel (default: the scene's, else 1)")
      ->check(in_range(1, kMaxSpp));
  add_scene_options(app, *o, kSizeOption | kThreadsOption | kSetOption, "(every scene)");
  app.add_option("--size", o->size, "longest image side, the scene's aspect kept")
      ->check(in_range(1, kMaxImageSide));
  app.add_option("--frames", o->frames, "timed frames per method after the warm-up frame")
      ->check(in_range(1, 1000));
  app.add_option("--band", o->bands,
                 "A,B: measure the band PSNR around objects A and B in scenes that have both "
                 "(repeatable; a scene of exactly two objects uses them anyway)");
  app.add_option("--radius", o->radius, "band half-width in pixels")->check(in_range(0, 4096));
  app.add_option("--band-opacity", o->band_opacity,
                 "accumulated opacity that counts as a volume's first hit for the band")
      ->check(in_range(0.0, 1.0));
  app.add_option("--heat-scale", o->heat_scale, "heat-map gain: an error of 1/scale is full heat")
      ->check(in_range(1e-6, 1e6));
  return [o]() {
    std::vector<std::vector<std::string>> pairs;
    for (const std::string& text : o->bands) {
      size_t comma = text.find(',');
      if (comma == std::string::npos || comma == 0 || comma + 1 == text.size() ||
          text.find(',', comma + 1) != std::string::npos)
        throw Error(fmt::format("--band '{}': expected two object names, A,B", text));
      pairs.push_back({text.substr(0, comma), text.substr(comma + 1)});
    }
    std::vector<std::string> methods = o->methods;
    const auto began = std::chrono::steady_clock::now();
    const std::vector<std::string> available = available_methods();
    if (methods.empty())
      for (const std::string& m : available)
        if (m != "reference") methods.push_back(m);
    for (const std::string& m : methods)
      if (std::find(available.begin(), available.end(), m) == available.end())
        throw Error(fmt::format("--method '{}' is not available; this build has: {}", m,
                                fmt::join(available, ", ")));
    if (o->width > 0 && o->size > 0) throw Error("--size and --width cannot both be given");
    if (o->height > 0 && o->size > 0) throw Error("--size and --height cannot both be given");

    std::vector<std::string> files = o->scenes;
    if (files.empty()) {
      std::error_code ec;
      for (const fs::directory_entry& e : fs::directory_iterator("examples", ec))
        if (e.path().extension() == ".json") files.push_back(e.path().string());
      std::sort(files.begin(), files.end());
      if (files.empty())
        throw Error("eval: no scenes given and no examples/*.json in the current folder");
    }

    // Every scene is loaded (and so validated) before anything is rendered or written.
    std::vector<Scene> scenes;
    for (const std::string& file : files) {
      scenes.push_back(load_scene(file, o->with_size()));
      if (o->size > 0) {
        Scene& sc = scenes.back();
        double scale = static_cast<double>(o->size) / std::max(sc.image.width, sc.image.height);
        int w = std::max(1, static_cast<int>(std::lround(sc.image.width * scale)));
        int h = std::max(1, static_cast<int>(std::lround(sc.image.height * scale)));
        sc.image.width = w;  // within the loader's limits: both sides shrink or grow to <= size
        sc.image.height = h;
      }
      print_notes(scenes.back().notes);
    }
    for (const auto& pair : pairs) {
      bool found = false;
      for (const Scene& sc : scenes) {
        std::vector<std::string> names = object_names(sc);
        auto has = [&](const std::string& n) {
          return std::find(names.begin(), names.end(), n) != names.end();
        };
        found = found || (has(pair[0]) && has(pair[1]));
      }
      if (!found)
        throw Error(fmt::format("--band {},{}: no scene has both objects", pair[0], pair[1]));
    }

    const fs::path dir = o->out;
    std::set<std::string> taken;
    EvalReport report;
    report.command = command_line();
    report.date = utc_now();
    report.threads = resolve_thread_count(o->threads);
    report.frames = o->frames;
    report.heat_scale = o->heat_scale;
    report.baseline = std::find(methods.begin(), methods.end(), "mdvr") != methods.end()
                          ? "mdvr"
                          : methods.front();
    for (size_t k = 0; k < scenes.size(); ++k) {
      SceneResult s;
      s.file = files[k];
      s.name = folder_name(files[k], taken);
      std::error_code ec;
      fs::create_directories(dir / s.name, ec);
      if (ec)
        throw Error(fmt::format("--out {}: cannot create {}: {}", dir.string(),
                                (dir / s.name).string(), ec.message()));
      // The scene's own description, read from its file (the Scene keeps none).
      try {
        std::ifstream in = try_open_input_stream(files[k]);
        nlohmann::json j = nlohmann::json::parse(in);
        if (j.contains("description") && j["description"].is_string())
          s.description = j["description"];
      } catch (const nlohmann::json::exception&) {
      }
      std::string tag = fmt::format("[{}/{}] {}", k + 1, scenes.size(), s.name);
      evaluate_scene(scenes[k], *o, methods, pairs, dir, tag, s);
      report.scenes.push_back(std::move(s));
    }

    report.seconds = ms_since(began) / 1000.0;
    write_text_atomically(dir / "eval.json", report_json(report).dump(1) + "\n");
    write_text_atomically(dir / "index.html", report_html(report));
    if (!o->markdown.empty()) write_text_atomically(o->markdown, report_markdown(report));
    progress(fmt::format("report in {}", (dir / "index.html").string()));
    return 0;
  };
}

}  // namespace imx::cli
