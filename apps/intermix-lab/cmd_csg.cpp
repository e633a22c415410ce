// intermix csg SCENE: a CSG scene's primitives, products, clipping states and rays' intervals.
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/parallel.hpp"
#include "csg/clip_state.hpp"
#include "csg/csg_expr.hpp"
#include "csg/state_table.hpp"
#include "frame/csg_frame.hpp"
#include "frame/frame_setup.hpp"
#include "intermix/error.hpp"
#include "intermix/scene.hpp"
#include "lab_commands.hpp"
#include "probes/csg_statistics.hpp"

namespace imx::cli {
namespace {

std::vector<std::string> digit_strings(const std::vector<ClipState>& states, int n) {
  std::vector<std::string> out;
  for (ClipState s : states) out.push_back(digits(s, n));
  return out;
}

// One stage of the table: its name in JSON and in text, and its states as digit strings.
struct Stage {
  const char* key;
  const char* label;
  std::vector<std::string> states;
};

// Everything `intermix csg` reports about the table, gathered once for both output forms.
struct CsgSummary {
  std::string simplify;
  std::vector<std::string> names, kinds, presences;
  std::string legend, expression;
  std::vector<Stage> stages;  // those the simplification level ran, products first
  std::vector<std::string> pruned, states;
};

CsgSummary summarize(const Scene& scene) {
  // The table exactly as render_csg builds it; CsgFrame's numbering is compile_expression's, so
  // the expression compiled here has the same digits.
  const FrameSetup frame(scene);
  const CsgFrame csg(scene, frame, /*with_states=*/true);
  std::vector<CsgPrimitive> primitives;
  const CsgExpr expr = compile_expression(*scene.csg, primitives);

  CsgSummary s;
  s.simplify = scene.render.csg_simplify;
  const int n = static_cast<int>(csg.primitives().size());
  for (int k = 0; k < n; ++k) {
    const CsgPrimitive& p = csg.primitives()[k];
    s.names.push_back(object_name(scene, p.object));
    s.kinds.push_back(p.object.kind == ObjectKind::volume ? "volume" : "mesh");
    s.presences.push_back(p.presence == CsgPresence::region ? "region" : "opacity");
    s.legend += fmt::format("{}{}={}", k ? " " : "", s.names.back(), k);
  }
  s.expression = to_string(expr, s.names);

  const CsgTableReport& r = csg.report();
  const CsgSimplify level = parse_csg_simplify(scene.render.csg_simplify);
  s.stages.push_back({"products", "products", digit_strings(r.products, n)});
  if (level != CsgSimplify::none) {
    s.stages.push_back({"merge", "after merge", digit_strings(r.after_merge, n)});
    s.stages.push_back({"pruning", "after pruning", digit_strings(r.after_pruning, n)});
  }
  if (level == CsgSimplify::full)
    s.stages.push_back({"full", "after full", digit_strings(r.after_full, n)});
  s.pruned = r.pruned;
  s.states = digit_strings(csg.table().states, n);
  return s;
}

// "label (n): a b c", wrapped below 100 columns with the continuation indented.
void print_list(const std::string& label, const std::vector<std::string>& items) {
  std::string line = fmt::format("{} ({}):", label, items.size());
  const size_t indent = 4;
  for (const std::string& item : items) {
    if (line.size() + 1 + item.size() > 100 && line.size() > indent) {
      std::printf("%s\n", line.c_str());
      line = std::string(indent - 1, ' ');
    }
    line += " " + item;
  }
  std::printf("%s\n", line.c_str());
}

void print_text(const std::string& file, const CsgSummary& s, const CsgRayStatistics* rays) {
  std::printf("%s: %zu CSG primitives, csg_simplify %s\n", file.c_str(), s.names.size(),
              s.simplify.c_str());
  for (size_t k = 0; k < s.names.size(); ++k)
    std::printf("  digit %-2zu %-16s %-6s presence %s\n", k, s.names[k].c_str(), s.kinds[k].c_str(),
                s.presences[k].c_str());
  std::printf("legend: %s (primitive 0 leftmost)\n", s.legend.c_str());
  std::printf("expression: %s\n", s.expression.c_str());
  for (const Stage& stage : s.stages) print_list(stage.label, stage.states);
  if (s.pruned.empty())
    std::printf("bounding-box pruning: nothing\n");
  else
    for (const std::string& line : s.pruned)
      std::printf("bounding-box pruning: %s\n", line.c_str());
  print_list("states", s.states);
  if (!rays) return;
  std::printf("intervals at %dx%d, 1 spp: %lld rays, %lld meet a CSG primitive\n", rays->width,
              rays->height, static_cast<long long>(rays->rays),
              static_cast<long long>(rays->meeting));
  std::printf("  intervals per ray (PSI): mean %.3f, max %d\n", rays->mean_intervals(),
              rays->max_intervals);
  std::printf("  accepted ranges per ray: mean %.3f, max %d\n", rays->mean_ranges(),
              rays->max_ranges);
  std::printf("  per-step test: %lld rays (%.1f%%)\n", static_cast<long long>(rays->tested),
              100.0 * rays->tested_fraction());
  std::string examples;
  for (const CsgPixel& p : rays->inconsistent_examples)
    examples += fmt::format(" ({}, {})", p.x, p.y);
  std::printf("  inconsistent rays: %lld%s%s\n", static_cast<long long>(rays->inconsistent),
              examples.empty() ? "" : ", e.g. at", examples.c_str());
}

nlohmann::json to_json(const std::string& file, const CsgSummary& s, const CsgRayStatistics* rays) {
  nlohmann::json primitives = nlohmann::json::array();
  for (size_t k = 0; k < s.names.size(); ++k)
    primitives.push_back(
        {{"name", s.names[k]}, {"digit", k}, {"kind", s.kinds[k]}, {"presence", s.presences[k]}});
  nlohmann::json stages = nlohmann::json::object();
  for (const Stage& stage : s.stages) stages[stage.key] = stage.states;
  nlohmann::json j = {
      {"scene", file},      {"simplify", s.simplify},     {"primitives", primitives},
      {"legend", s.legend}, {"expression", s.expression}, {"products", s.stages.front().states},
      {"stages", stages},   {"pruned", s.pruned},         {"states", s.states}};
  if (rays) {
    nlohmann::json examples = nlohmann::json::array();
    for (const CsgPixel& p : rays->inconsistent_examples) examples.push_back({p.x, p.y});
    j["intervals"] = {
        {"width", rays->width},
        {"height", rays->height},
        {"rays", rays->rays},
        {"meeting", rays->meeting},
        {"intervals_per_ray", {{"mean", rays->mean_intervals()}, {"max", rays->max_intervals}}},
        {"ranges_per_ray", {{"mean", rays->mean_ranges()}, {"max", rays->max_ranges}}},
        {"tested", rays->tested},
        {"tested_fraction", rays->tested_fraction()},
        {"inconsistent", rays->inconsistent},
        {"inconsistent_examples", examples}};
  }
  return j;
}

}  // namespace

Command add_csg(CLI::App& app) {
  struct Options : SceneOptions {
    std::string scene;
    bool json = false, intervals = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("scene", o->scene, "scene file (JSON) with a csg block")->required();
  app.add_flag("--json", o->json, "print one JSON object on stdout");
  app.add_flag("--intervals", o->intervals,
               "also classify one ray per pixel as the csg method does: intervals per ray (PSI), "
               "accepted ranges, per-step tests, inconsistent rays");
  add_scene_options(app, *o, kSizeOption | kThreadsOption, "for --intervals");
  add_scene_options(app, *o, kSetOption);
  return [o]() {
    const std::vector<std::string> overrides = o->with_size();
    const Scene scene = load_scene(o->scene, overrides);
    if (!scene.csg) throw Error(fmt::format("{}: has no csg block", o->scene));
    CsgSummary summary;
    CsgRayStatistics rays;
    try {
      summary = summarize(scene);
      if (o->intervals) rays = csg_ray_statistics(scene, o->threads);
    } catch (const Error& e) {
      // The table's errors name counts and primitives, not the file.
      throw Error(fmt::format("{}: {}", o->scene, e.what()));
    }
    const CsgRayStatistics* stats = o->intervals ? &rays : nullptr;
    if (o->json)
      std::printf("%s\n", to_json(o->scene, summary, stats).dump().c_str());
    else
      print_text(o->scene, summary, stats);
    return 0;
  };
}

}  // namespace imx::cli
