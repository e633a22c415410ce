// The bytes a render writes at one pixel of its PNG: what a user's image viewer shows, for the
// colour tests (what you give is what you see).
#pragma once
#include <filesystem>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "intermix/io.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "temp_dir.hpp"

namespace imx::test {

// The centre pixel's bytes of `scene` (16x16) rendered with `method` into a PNG in `dir`.
inline glm::ivec3 centre_png_bytes(const TempDir& dir, const Scene& scene, const char* method) {
  RenderOptions options;
  options.method = method;
  options.threads = 1;
  // A file per render: one read by this process is an input, which no later write replaces.
  const std::filesystem::path out = dir / fmt::format("out-{}.png", method);
  write_png(render(scene, options), out);
  const Image png = read_png(out, true);  // the stored bytes
  return glm::ivec3(glm::round(glm::vec3(png.at(8, 8)) * 255.0f));
}

}  // namespace imx::test
