// Every render method on a tiny scene built around fuzzed voxels: an 8x8 image, 1 sample per
// pixel, 1 thread. The bytes choose the scene; what is left is the voxel data of a volume of at
// most 8x8x8 voxels, repeated to fill it (zeros when there is none). Every method must return
// an 8x8 image of finite values or throw imx::Error (e.g. a non-CSG method on a CSG scene).
//
// byte 0: bits 0-1 voxel type (u8, i16, u16, f32); 2-3 style (dvr, iso, mip, xray);
//         4 shading; 5 pre-integrated classification (else post); 6 a sphere mesh; 7 an MPR
//         plane on the volume
// byte 1: bits 0-1, 2-3, 4-5 dims along i, j, k (2, 4, 6, 8); 6 a second, turned copy of the
//         volume; 7 a csg block (volume minus the sphere)
// byte 2: bits 0-1 skipping (none, bricks, distance, distance); 2 on-the-fly gradients;
//         3 orthographic; 4-5 interpolation (ovi, hvi, blend, ovi); 6 exclusive mixing;
//         7 rgba8 slabs
// byte 3: bits 0-1 k-1; 2 layers 4 or 8; 3 tail overflow; 4-7 fragment_cap-1; 1-2 also the
//         brick size; 6-7 the TF preset of pre-integrated integer volumes
// bytes 4-11: two float32 transfer-function values; bytes 12-13: their opacities (/255); these
//         are replaced by a preset for pre-integrated integer volumes (see below)
// byte 14: low 4 bits 1-12 render only that method of available_methods() (faster runs that
//         still reach every method); 0 and 13-15 render every method; bit 4 turns mip into
//         minip and xray into its average mode; bit 5 makes some float voxels no data: with
//         bits 6-7 choosing which (NaN, +inf, -inf, all three), those whose index i has
//         (i * 5 + byte 3) % 7 < 1 + 2 * (byte 0 bit 4) (and voxels read as NaN or inf anyway)
// bytes 15-: voxels, little-endian
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "harness.hpp"
#include "intermix/render.hpp"
#include "intermix/scene.hpp"

namespace {

constexpr size_t kHeader = 15;
constexpr int kImage = 8;

uint8_t byte(const uint8_t* data, size_t size, size_t i) {
  return i < size ? data[i] : 0;
}

double tf_value(const uint8_t* data, size_t size, size_t at, double fallback) {
  uint8_t b[4];
  for (size_t i = 0; i < 4; ++i) b[i] = byte(data, size, at + i);
  float f;
  std::memcpy(&f, b, 4);
  // Scene numbers must be finite floats: keep the JSON loadable so the render runs.
  if (!std::isfinite(f) || std::fabs(f) > 1e30f) return fallback;
  return f;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const uint8_t b0 = byte(data, size, 0), b1 = byte(data, size, 1), b2 = byte(data, size, 2),
                b3 = byte(data, size, 3);

  // The volume: a NRRD with raw little-endian voxels, 5 mm apart, centred on the origin.
  static const char* const kTypes[] = {"uint8", "int16", "uint16", "float"};
  static const size_t kSizes[] = {1, 2, 2, 4};
  const int type = b0 & 3;
  const int nx = 2 + 2 * (b1 & 3), ny = 2 + 2 * ((b1 >> 2) & 3), nz = 2 + 2 * ((b1 >> 4) & 3);
  const size_t bytes = static_cast<size_t>(nx) * ny * nz * kSizes[type];
  std::string voxels(bytes, '\0');
  if (size > kHeader)
    for (size_t i = 0; i < bytes; ++i)
      voxels[i] = static_cast<char>(data[kHeader + i % (size - kHeader)]);
  const uint8_t b14 = byte(data, size, 14);
  if (type == 3 && (b14 & 0x20) != 0) {
    // No data (NaN and inf voxels, as outside a statistical map's mask) is valid input.
    static const float kNoData[] = {NAN, INFINITY, -INFINITY};
    const int which = (b14 >> 6) & 3;
    const size_t every = 1 + 2 * ((b0 >> 4) & 1);
    for (size_t i = 0; i < bytes / 4; ++i)
      if ((i * 5 + b3) % 7 < every) {
        const float f = kNoData[which == 3 ? i % 3 : which];
        std::memcpy(&voxels[4 * i], &f, 4);
      }
  }
  const double sp = 5.0;
  std::string nrrd = fmt::format(
      "NRRD0004\ntype: {}\ndimension: 3\nsizes: {} {} {}\nspace: left-posterior-superior\n"
      "space directions: ({},0,0) (0,{},0) (0,0,{})\nspace origin: ({},{},{})\n"
      "encoding: raw\nendian: little\n\n",
      kTypes[type], nx, ny, nz, sp, sp, sp, -0.5 * sp * (nx - 1), -0.5 * sp * (ny - 1),
      -0.5 * sp * (nz - 1));
  dir.write("vol.nrrd", nrrd + voxels);

  // The scene.
  const bool post = (b0 & 0x20) == 0;
  double v0 = tf_value(data, size, 4, 0.0), v1 = tf_value(data, size, 8, 100.0);
  if (v1 < v0) std::swap(v0, v1);
  double a0 = byte(data, size, 12) / 255.0, a1 = byte(data, size, 13) / 255.0;
  if (!post && type != 3) {
    // A pre-integration table costs most of a run, and it is cached by (TF, step, value range):
    // for integer voxels the TF is one of 4 presets over the type's whole range, so the table is
    // built once. Float voxels keep the fuzzed TF and range (the slow, general case).
    static const double kLo[] = {0, -32768, 0}, kHi[] = {255, 32767, 65535};
    static const double kAlpha[][2] = {{0, 1}, {1, 0}, {0.1, 0.3}, {0.5, 0.5}};
    const int preset = (b3 >> 6) & 3;
    v0 = kLo[type];
    v1 = kHi[type];
    a0 = kAlpha[preset][0];
    a1 = kAlpha[preset][1];
  }
  static const char* const kStyles[] = {"dvr", "iso", "mip", "xray"};
  const char* style = kStyles[(b0 >> 2) & 3];
  const bool variant = (b14 & 0x10) != 0;
  if (variant && std::string_view(style) == "mip") style = "minip";
  const char* xray_mode = variant && std::string_view(style) == "xray" ? "average" : "integral";
  const bool shading = (b0 & 0x10) != 0, plane = (b0 & 0x80) != 0;
  const bool second = (b1 & 0x40) != 0, csg = (b1 & 0x80) != 0;
  const bool mesh = (b0 & 0x40) != 0 || csg;
  static const char* const kSkipping[] = {"none", "bricks", "distance", "distance"};
  static const char* const kInterpolation[] = {"ovi", "hvi", "blend", "ovi"};
  const bool ortho = (b2 & 0x08) != 0, exclusive = (b2 & 0x40) != 0 && second;

  std::string volume_fields = fmt::format(
      R"("type": "volume", "source": {{"file": "vol.nrrd"}}, "style": "{}", "iso_value": {},{}
         "transfer_function": {{"points": [[{}, 1, 0.8, 0.6, {}], [{}, 0.6, 0.8, 1, {}]],
                                "unit_distance": 5}},
         "shading": {{"enabled": {}}})",
      style, 0.5 * v0 + 0.5 * v1,
      std::string_view(style) == "xray" ? fmt::format(R"( "xray_mode": "{}",)", xray_mode) : "", v0,
      a0, v1, a1, shading ? "true" : "false");
  std::string objects = fmt::format(R"({{"name": "v", {}}})", volume_fields);
  if (second)
    objects += fmt::format(
        R"(, {{"name": "w", {}, "transform": {{"rotate_deg": [0, 0, 30], "translate": [4, 0, 2]}}}})",
        volume_fields);
  if (mesh)
    objects += R"(, {"name": "ball", "type": "mesh",
                     "source": {"primitive": "sphere", "radius": 9, "segments": 8},
                     "transform": {"translate": [3, -2, 1]},
                     "material": {"color": [0.2, 0.5, 1], "opacity": 0.5}})";
  if (plane)
    objects += fmt::format(
        R"(, {{"name": "mpr", "type": "plane", "volume": "v", "normal": [0.3, 0.2, 1],
               "window": [{}, {}], "opacity": 0.7}})",
        0.5 * v0 + 0.5 * v1, std::max(v1 - v0, 1.0));
  std::string json = fmt::format(
      R"({{"camera": {{"eye": [10, -150, 40], "target": [0, 0, 0], "up": [0, 0, 1],
                      "fov_deg": 30, "projection": "{}", "ortho_height": 60}},
          "image": {{"width": {}, "height": {}, "background": [0.1, 0.1, 0.1, 1]}},
          "objects": [{}],
          {}
          "render": {{"spp": 1, "skipping": "{}", "classification": "{}", "gradients": "{}",
                      "interpolation": "{}", "mixing": "{}", "slab_format": "{}",
                      "k": {}, "layers": {}, "overflow": "{}", "fragment_cap": {},
                      "brick_size": {}, "peel_layers": 2}}}})",
      ortho ? "orthographic" : "perspective", kImage, kImage, objects,
      csg ? R"("csg": {"op": "difference", "a": "v", "b": "ball"},)" : "", kSkipping[b2 & 3],
      post ? "post" : "preintegrated", (b2 & 0x04) != 0 ? "on-the-fly" : "precomputed",
      kInterpolation[(b2 >> 4) & 3], exclusive ? "exclusive" : "inclusive",
      (b2 & 0x80) != 0 ? "rgba8" : "rgba32f", 1 + (b3 & 3), (b3 & 4) != 0 ? 8 : 4,
      (b3 & 8) != 0 ? "tail" : "greedy", 1 + (b3 >> 4), 2 + (b3 & 6));
  std::filesystem::path file = dir.write("scene.json", json);

  imx::Scene scene;
  try {
    scene = imx::load_scene(file);
  } catch (const std::exception& e) {
    refused(e);  // a volume the reader refuses
    return 0;
  }
  const std::vector<std::string> methods = imx::available_methods();
  const size_t only = b14 & 15;
  for (size_t m = 0; m < methods.size(); ++m) {
    if (only >= 1 && only <= methods.size() && m != only - 1) continue;
    const std::string& method = methods[m];
    imx::RenderOptions options;
    options.method = method;
    options.spp = 1;
    options.threads = 1;
    imx::Image image;
    try {
      image = imx::render(scene, options);
    } catch (const std::exception& e) {
      refused(e);
      continue;
    }
    accepted(method.c_str());
    if (image.width() != kImage || image.height() != kImage) {
      std::fprintf(stderr, "fuzz_render: %s returned a %dx%d image\n", method.c_str(),
                   image.width(), image.height());
      __builtin_trap();
    }
    for (size_t i = 0; i < image.size(); ++i) {
      const glm::vec4& p = image.data()[i];
      if (!std::isfinite(p.r) || !std::isfinite(p.g) || !std::isfinite(p.b) ||
          !std::isfinite(p.a)) {
        std::fprintf(stderr, "fuzz_render: %s gave a non-finite pixel %zu (%g %g %g %g)\n",
                     method.c_str(), i, p.r, p.g, p.b, p.a);
        __builtin_trap();
      }
    }
  }
  return 0;
}
