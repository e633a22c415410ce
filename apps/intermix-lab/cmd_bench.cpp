// intermix bench SCENE: ms per frame of methods and setting variants on one scene (and of the VTK
// peer with --vtk), in one run, so their ratios are comparable.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "bench_change.hpp"
#include "core/parallel.hpp"
#include "core/process_usage.hpp"
#include "core/progress_bar.hpp"
#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "lab_commands.hpp"
#include "methods/resident_memory.hpp"
#include "volume/simd_targets.hpp"
#include "vtk_peer_runner.hpp"

namespace imx::cli {

namespace {

// The camera turned about the target's vertical by `degrees`, so each frame is really rendered.
Camera jittered(const Camera& camera, double degrees) {
  glm::dmat4 turn = glm::rotate(glm::dmat4(1.0), glm::radians(degrees), camera.up);
  Camera c = camera;
  c.eye = camera.target + glm::dvec3(turn * glm::dvec4(camera.eye - camera.target, 0.0));
  return c;
}

// One --variant: a label and the --set assignments it adds.
struct Variant {
  std::string label;
  std::vector<std::string> overrides;
};

// "LABEL:key=value,key=value"; commas inside [] {} or quotes belong to the value.
Variant parse_variant(const std::string& text) {
  size_t colon = text.find(':');
  if (colon == std::string::npos || colon == 0)
    throw Error(
        fmt::format("--variant '{}': expected LABEL:key=value,key=value (or LABEL:)", text));
  Variant v{text.substr(0, colon), {}};
  std::string current;
  int depth = 0;
  bool in_quotes = false;
  auto flush = [&] {
    if (current.find_first_not_of(" \t") == std::string::npos) {
      current.clear();
      return;
    }
    if (current.find('=') == std::string::npos)
      throw Error(fmt::format("--variant '{}': '{}' is not key=value", text, current));
    v.overrides.push_back(current);
    current.clear();
  };
  for (char c : text.substr(colon + 1)) {
    if (c == '"') in_quotes = !in_quotes;
    if (!in_quotes && (c == '[' || c == '{')) ++depth;
    if (!in_quotes && (c == ']' || c == '}')) --depth;
    if (c == ',' && depth == 0 && !in_quotes)
      flush();
    else
      current += c;
  }
  flush();
  return v;
}

double median_of(std::vector<double> ms) {
  std::sort(ms.begin(), ms.end());
  size_t n = ms.size();
  return n % 2 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2]);
}

// One timed row: a method on one variant's scene.
struct BenchRow {
  const Scene* scene = nullptr;
  RenderOptions options;
  std::string label, variant;  // variant: empty unless variants are named
  std::vector<double> ms;
  double peak_mib = 0.0;
  ChangeTiming change;  // with --change: the stages of the frame and those re-run
};

// Times `frames` renders of every row, in rounds that render each row once, so that a machine
// that slows down or speeds up during the run weighs on every row alike. Each row has one
// warm-up render first (caches, page faults, thread pool); its peak memory is read after it.
void time_rounds(std::vector<BenchRow>& rows, int frames) {
  ProgressBar bar("bench", show_progress());
  const double total = static_cast<double>(rows.size()) * (frames + 1);
  int done = 0;
  for (BenchRow& row : rows) {
    try {
      render(*row.scene, row.options);
    } catch (const Error& e) {
      throw Error(fmt::format("{}: row {}: {}", row.scene->file.string(), row.label, e.what()));
    }
    row.peak_mib = peak_resident_bytes() / 1048576.0;
    bar.update(++done / total);
  }
  for (int f = 0; f < frames; ++f) {
    for (BenchRow& row : rows) {
      Scene frame = *row.scene;
      frame.camera = jittered(row.scene->camera, f % 2 == 0 ? 0.5 : -0.5);
      auto start = std::chrono::steady_clock::now();
      render(frame, row.options);
      row.ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count());
      bar.update(++done / total);
    }
  }
  bar.finish();
}

}  // namespace

Command add_bench(CLI::App& app) {
  struct Options : SceneOptions {
    std::string scene, peer, vtk_mode = "cpu", change, peer_scene_dir;
    std::vector<std::string> methods, variants;
    int frames = 5;
    bool json = false, vtk = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("scene", o->scene, "scene file (JSON)")->required();
  app.add_option("--method", o->methods, "method to time (repeatable; default: the scene's)");
  app.add_option("--variant", o->variants,
                 "LABEL:key=value,key=value: extra --set overrides timed as their own row for "
                 "every method (repeatable; 'LABEL:' alone is the scene as it is)");
  app.add_option("--frames", o->frames, "timed frames after one warm-up frame")
      ->check(in_range(1, 100000));
  add_scene_options(app, *o);
  app.add_flag("--vtk", o->vtk,
               "also time the VTK peer (vtk_peer.py) on the same scene, image size and sample "
               "distance (needs scripts/install-deps --with-peers)");
  app.add_option("--vtk-mode", o->vtk_mode, "the VTK peer's mapper: cpu or gpu")
      ->check(CLI::IsMember({"cpu", "gpu"}));
  app.add_option("--peer", o->peer,
                 "vtk_peer.py (default: shared/peers/vtk_peer.py in the nearest folder above "
                 "this program, else above the scene)");
  app.add_option("--write-peer-scene", o->peer_scene_dir,
                 "write the scene as the VTK peer gets it (volumes as MetaImage in the first "
                 "volume's frame, meshes as OBJ) into this new folder, and time nothing");
  app.add_flag("--json", o->json, "print one JSON object on stdout");
  app.add_option("--change", o->change,
                 "time re-renders after OBJECT.key=value, keeping stage outputs (zslab methods)");
  return [o]() {
    const std::vector<std::string> overrides = o->with_size();
    std::vector<Variant> variants;
    for (const std::string& text : o->variants) {
      variants.push_back(parse_variant(text));
      for (size_t i = 0; i + 1 < variants.size(); ++i)
        if (variants[i].label == variants.back().label)
          throw Error(fmt::format("--variant: label '{}' is given twice", variants.back().label));
    }
    const bool named = !variants.empty();
    if (!named) variants.push_back({});

    // Every variant's scene is loaded (and validated) before anything is timed.
    std::vector<std::vector<std::string>> assignments;
    std::vector<Scene> scenes;
    for (const Variant& variant : variants) {
      assignments.push_back(overrides);
      assignments.back().insert(assignments.back().end(), variant.overrides.begin(),
                                variant.overrides.end());
      scenes.push_back(load_scene(o->scene, assignments.back()));
    }
    const Scene& base = scenes.front();
    print_notes(base.notes);
    std::vector<std::string> methods = o->methods;
    if (methods.empty()) methods.push_back(base.render.method);

    // The peer renders the first variant's scene; it is checked before anything is timed, so a
    // missing tool fails at once.
    PeerRun run{.peer = o->peer.empty() ? find_vtk_peer(o->scene) : std::filesystem::path(o->peer),
                .scene_file = o->scene,
                .overrides = assignments.front(),
                .scene = &base,
                .mode = o->vtk_mode,
                .frames = o->frames,
                .sample_distance_mm = peer_sample_distance(base),
                .notes = !quiet()};
    if (!o->peer_scene_dir.empty()) {
      const std::filesystem::path dir = o->peer_scene_dir;
      std::error_code ec;
      if (!std::filesystem::create_directory(dir, ec))
        throw Error(fmt::format("--write-peer-scene: cannot create the new folder '{}'{}",
                                dir.string(), ec ? ": " + ec.message() : " (it exists)"));
      std::printf("%s\n", write_peer_scene(run, dir).string().c_str());
      return 0;
    }
    if (o->vtk) {
      if (run.peer.empty())
        throw Error(fmt::format(
            "bench --vtk: cannot find shared/peers/vtk_peer.py above this program or above {}; "
            "give --peer PATH",
            o->scene));
      check_vtk_peer(run.peer);
    }

    // The rows in order, timed in rounds (or, with --change, one after another, since each
    // re-render follows a render of the unchanged scene).
    std::vector<BenchRow> timed;
    for (const std::string& method : methods) {
      for (size_t v = 0; v < variants.size(); ++v) {
        BenchRow row;
        row.scene = &scenes[v];
        row.label = method;
        row.options.method = method;
        row.options.spp = o->spp;
        row.options.threads = o->threads;
        if (named) {
          row.variant = variants[v].label;
          row.label = fmt::format("{}/{}", method, row.variant);
        }
        if (!o->change.empty()) {
          row.change =
              time_change(scenes[v], o->scene, assignments[v], o->change, row.options, o->frames);
          row.ms = row.change.ms;
          row.peak_mib = peak_resident_bytes() / 1048576.0;
        }
        timed.push_back(std::move(row));
      }
    }
    if (o->change.empty()) time_rounds(timed, o->frames);

    nlohmann::json rows = nlohmann::json::array();
    for (const BenchRow& row : timed) {
      const Scene& scene = *row.scene;
      const std::string& method = row.options.method;
      double median = median_of(row.ms);
      int spp = o->spp > 0 ? o->spp : scene.render.spp > 0 ? scene.render.spp : default_spp(method);
      double rays = static_cast<double>(scene.image.width) * scene.image.height * spp;
      rows.push_back({{"label", row.label},
                      {"method", method},
                      {"variant", row.variant},
                      {"frames", o->frames},
                      {"ms_median", median},
                      {"ms_min", *std::min_element(row.ms.begin(), row.ms.end())},
                      {"ms_max", *std::max_element(row.ms.begin(), row.ms.end())},
                      {"rays_per_s", rays / (median / 1000.0)},
                      {"peak_rss_mib", row.peak_mib}});
      if (!o->change.empty()) {
        const double fresh = median_of(row.change.fresh_ms);
        rows.back().update({{"change", o->change},
                            {"stages", row.change.stages},
                            {"stages_run", row.change.stages_run},
                            {"stages_merged", row.change.stages_merged},
                            {"kept_bytes_per_pixel", row.change.kept_bytes_per_pixel},
                            {"fresh_ms_median", fresh},
                            {"vs_fresh", median / fresh}});
      }
    }

    if (o->vtk) {
      if (!quiet())
        std::fprintf(stderr, "intermix-lab: bench vtk-%s (sample distance %g mm)\n",
                     o->vtk_mode.c_str(), run.sample_distance_mm);
      PeerTiming t = run_vtk_peer(run);
      double rays = static_cast<double>(base.image.width) * base.image.height;
      std::string label = "vtk-" + o->vtk_mode;
      rows.push_back({{"label", label},
                      {"method", label},
                      {"variant", ""},
                      {"frames", o->frames},
                      {"ms_median", t.ms_median},
                      {"ms_min", t.ms_min},
                      {"ms_max", t.ms_max},
                      {"rays_per_s", rays / (t.ms_median / 1000.0)},
                      {"peak_rss_mib", t.peak_rss_mib},
                      {"sample_distance_mm", run.sample_distance_mm},
                      {"first_image_ms", t.first_image_ms},
                      {"empty_image", t.empty_image}});
      if (t.empty_image && !quiet())
        std::fprintf(stderr,
                     "intermix-lab: warning: VTK drew an empty image; its time measures no "
                     "rendering\n");
    }

    // What each variant's volumes hold resident under the first method timed (the structures its
    // frames built, from the caches).
    nlohmann::json resident = nlohmann::json::array();
    for (size_t v = 0; v < scenes.size(); ++v) {
      const std::vector<std::vector<ResidentPart>> held =
          resident_parts(scenes[v], resolve_method(scenes[v], methods.front()).name);
      for (size_t k = 0; k < held.size(); ++k) {
        nlohmann::json parts = nlohmann::json::array();
        for (const ResidentPart& part : held[k])
          parts.push_back({{"name", part.name}, {"bytes", part.bytes}});
        resident.push_back({{"variant", variants[v].label},
                            {"volume", scenes[v].volumes[k].name},
                            {"parts", parts}});
      }
    }

    const double first = rows.front()["ms_median"];
    for (auto& r : rows) r["ratio"] = r["ms_median"].get<double>() / first;
    if (o->json) {
      nlohmann::json out = {{"scene", o->scene},           {"width", base.image.width},
                            {"height", base.image.height}, {"simd", simd_target()},
                            {"simd_lanes", simd_lanes()},  {"methods", rows},
                            {"resident", resident}};
      std::printf("%s\n", out.dump().c_str());
    } else {
      std::printf("%s at %dx%d, lanes %s (%d floats)\n", o->scene.c_str(), base.image.width,
                  base.image.height, simd_target().c_str(), simd_lanes());
      const std::string first_label = rows.front()["label"];
      for (const auto& r : rows) {
        std::printf("  %-24s median %9.1f ms  min %9.1f  max %9.1f  (x%.2f of %s)  peak %.0f MiB\n",
                    r["label"].get<std::string>().c_str(), r["ms_median"].get<double>(),
                    r["ms_min"].get<double>(), r["ms_max"].get<double>(), r["ratio"].get<double>(),
                    first_label.c_str(), r["peak_rss_mib"].get<double>());
        if (r.contains("vs_fresh"))
          std::printf(
              "  %-24s %d of %d stages run, %d merged: x%.2f of a fresh frame (%.1f ms), "
              "%.0f B/pixel kept\n",
              "", r["stages_run"].get<int>(), r["stages"].get<int>(), r["stages_merged"].get<int>(),
              r["vs_fresh"].get<double>(), r["fresh_ms_median"].get<double>(),
              r["kept_bytes_per_pixel"].get<double>());
      }
      for (const auto& r : resident) {
        std::string line;
        uint64_t total = 0;
        for (const auto& part : r["parts"]) {
          const uint64_t bytes = part["bytes"];
          total += bytes;
          if (bytes)
            line += fmt::format(", {} {}", part["name"].get<std::string>(), format_bytes(bytes));
        }
        const std::string variant = r["variant"];
        std::printf("  resident %s%s'%s': %s%s\n", variant.c_str(), variant.empty() ? "" : " ",
                    r["volume"].get<std::string>().c_str(), format_bytes(total).c_str(),
                    line.empty() ? "" : (" =" + line.substr(1)).c_str());
      }
    }
    return 0;
  };
}

}  // namespace imx::cli
