// EvalReport: what `intermix eval` measured, and its three renderings: JSON, HTML and Markdown.
#pragma once
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "intermix/metrics.hpp"

namespace imx::cli {

// One method on one scene. Paths are relative to the report's folder.
struct MethodResult {
  std::string method;
  bool ok = false;
  std::string error;  // when !ok: the first line of what the method refused
  int spp = 0;
  std::string image, heat_map;
  ImageComparison quality;
  double band_psnr_db = std::numeric_limits<double>::quiet_NaN();  // NaN: no band
  double ms_median = 0.0, ms_min = 0.0, ms_max = 0.0;
  double stage_bytes_per_pixel = 0.0;  // stage buffers the method reports; 0: it reports none
  double peak_rss_delta_mib = -1.0;    // peak resident memory over the frame's start; < 0: unknown
};

struct SceneResult {
  std::string name;  // also the scene's folder in the report
  std::string file, description;
  int width = 0, height = 0;
  int reference_spp = 0;
  double reference_ms = 0.0;
  std::string reference_image;
  std::vector<std::string> band_objects;  // empty: no band PSNR for this scene
  int band_radius = 0;
  long band_pixels = 0;
  std::string band_mask;
  std::vector<MethodResult> methods;
};

struct EvalReport {
  std::string command;   // the command line that made it
  std::string date;      // UTC, ISO 8601
  double seconds = 0.0;  // wall time of the whole evaluation
  std::string baseline;  // the method speed ratios are taken against
  int threads = 0, frames = 0;
  double heat_scale = 0.0;
  std::vector<SceneResult> scenes;
};

// One method over every scene.
struct MethodSummary {
  std::string method;
  int scenes = 0, not_applicable = 0;
  double psnr_mean_db = 0.0, psnr_min_db = 0.0, ssim_mean = 0.0;
  std::string psnr_min_scene;
  double band_psnr_mean_db = std::numeric_limits<double>::quiet_NaN();
  double ms_median = 0.0;  // median over its scenes of the per-scene median
  double time_ratio = std::numeric_limits<double>::quiet_NaN();  // geometric mean vs baseline
};

// PSNR of identical images is +inf; means count it as this many dB.
inline constexpr double kPsnrCapDb = 100.0;

std::vector<MethodSummary> summarize(const EvalReport& report);
nlohmann::json report_json(const EvalReport& report);
std::string report_html(const EvalReport& report);
std::string report_markdown(const EvalReport& report);

}  // namespace imx::cli
