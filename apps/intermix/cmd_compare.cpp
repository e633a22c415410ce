// intermix compare A.png B.png: image quality metrics of B against A.
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include "commands.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/metrics.hpp"

namespace imx::cli {

Command add_compare(CLI::App& app) {
  struct Options {
    std::string a, b, heat_map;
    double scale = 16.0;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("a", o->a, "first image (the reference)")->required();
  app.add_option("b", o->b, "second image")->required();
  app.add_option("--heat-map", o->heat_map, "write a PNG heat map of the per-pixel error");
  app.add_option("--scale", o->scale, "heat-map gain: an error of 1/scale is full heat")
      ->check(in_range(1e-6, 1e6));
  app.add_flag("--json", o->json, "print one JSON object on stdout");
  return [o]() {
    Image a = read_png(o->a), b = read_png(o->b);
    if (a.width() != b.width() || a.height() != b.height())
      throw Error(fmt::format("images differ in size: {} is {}x{}, {} is {}x{}", o->a, a.width(),
                              a.height(), o->b, b.width(), b.height()));
    ImageComparison c = compare_images(a, b);
    if (!o->heat_map.empty()) write_png(error_heat_map(a, b, o->scale), o->heat_map);
    if (o->json) {
      nlohmann::json j = {
          {"psnr_db", std::isinf(c.psnr_db) ? nlohmann::json("inf") : nlohmann::json(c.psnr_db)},
          {"ssim", c.ssim},
          {"max_error", c.max_error},
          {"frac_over_1", c.frac_over_1},
          {"frac_over_4", c.frac_over_4},
          {"frac_over_16", c.frac_over_16}};
      std::printf("%s\n", j.dump().c_str());
    } else {
      std::printf(
          "PSNR %.2f dB  SSIM %.5f  max error %.4f  >1/255 %.4f  >4/255 %.4f  >16/255 %.4f\n",
          c.psnr_db, c.ssim, c.max_error, c.frac_over_1, c.frac_over_4, c.frac_over_16);
    }
    return 0;
  };
}

}  // namespace imx::cli
