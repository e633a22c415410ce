// intermix band SCENE REF.png IMAGE.png...: PSNR in the band around two objects' intersection.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "intermix/band_metrics.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/metrics.hpp"
#include "intermix/scene.hpp"
#include "lab_commands.hpp"
#include "probes/first_hit_depth.hpp"

namespace imx::cli {

Command add_band(CLI::App& app) {
  struct Options {
    std::string scene, reference, mask_out;
    std::vector<std::string> images, objects;
    int radius = 2;
    float opacity = 0.5f;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("scene", o->scene, "scene file the images show")->required();
  app.add_option("reference", o->reference, "reference image")->required();
  app.add_option("images", o->images, "images to measure")->required();
  app.add_option("--objects", o->objects, "the two intersecting objects")
      ->required()
      ->delimiter(',')
      ->expected(2);
  app.add_option("--radius", o->radius, "band half-width in pixels")->check(in_range(0, 4096));
  app.add_option("--opacity", o->opacity, "accumulated opacity that counts as a volume's hit")
      ->check(in_range(0.0, 1.0));
  app.add_option("--mask-out", o->mask_out, "write the band as a PNG mask");
  app.add_flag("--json", o->json, "print one JSON object on stdout");
  return [o]() {
    Image ref = read_png(o->reference);
    Scene scene = load_scene(o->scene);
    scene.image.width = ref.width();
    scene.image.height = ref.height();
    std::vector<uint8_t> band =
        intersection_band(first_hit_depth(scene, o->objects[0], o->opacity),
                          first_hit_depth(scene, o->objects[1], o->opacity), o->radius);
    long pixels = 0;
    for (uint8_t b : band) pixels += b;
    if (!o->mask_out.empty()) {
      Image mask(ref.width(), ref.height(), glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
      for (size_t i = 0; i < band.size(); ++i)
        if (band[i]) mask.data()[i] = glm::vec4(1.0f);
      write_png(mask, o->mask_out);
    }
    auto num = [](double v) {
      return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(std::isnan(v) ? "nan" : "inf");
    };
    nlohmann::json out = {{"band_pixels", pixels}, {"images", nlohmann::json::array()}};
    for (const std::string& f : o->images) {
      Image img = read_png(f);
      double in_band = masked_psnr(ref, img, band), all = psnr(ref, img);
      if (o->json)
        out["images"].push_back(
            {{"image", f}, {"band_psnr_db", num(in_band)}, {"psnr_db", num(all)}});
      else
        std::printf("%s: band PSNR %.2f dB (%ld pixels)  PSNR %.2f dB\n", f.c_str(), in_band,
                    pixels, all);
    }
    if (o->json) std::printf("%s\n", out.dump().c_str());
    return 0;
  };
}

}  // namespace imx::cli
