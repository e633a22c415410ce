// "visible": false renders the same bytes as leaving the object out, in every method, when
// nothing else refers to it: a hidden mesh or plane makes no fragment that changes the image.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "intermix/render.hpp"
#include "intermix/scene.hpp"
#include "same_image.hpp"

namespace imx {
namespace {

constexpr int kSize = 64;

const char* const kMethods[] = {"reference",   "mdvr",  "peel",  "dfb",   "dfb-sfm",     "kbuffer",
                                "kbuffer-ofm", "wboit", "mboit", "zslab", "zslab-hybrid"};

// An example's JSON at kSize pixels with its ct-head phantom at 48 voxels.
nlohmann::json example(const std::string& name) {
  std::ifstream in(std::filesystem::path(IMX_EXAMPLES_DIR) / name);
  nlohmann::json j = nlohmann::json::parse(in);
  j["image"]["width"] = kSize;
  j["image"]["height"] = kSize;
  for (nlohmann::json& o : j["objects"])
    if (o.contains("source") && o["source"].contains("phantom")) o["source"]["size"] = 48;
  return j;
}

Scene load(const nlohmann::json& j, const std::string& origin) {
  return parse_scene(j.dump(), IMX_EXAMPLES_DIR, origin);
}

using test::same_bytes;

// Object `index` of example `name` hidden, and left out: the same image in every method; and
// shown, a different one (so the object is in view).
void expect_hidden_is_absent(const std::string& name, size_t index) {
  nlohmann::json hidden = example(name), absent = example(name);
  const nlohmann::json shown = example(name);
  hidden["objects"][index]["visible"] = false;
  absent["objects"].erase(index);
  const Scene h = load(hidden, "hidden"), a = load(absent, "absent"), s = load(shown, "shown");
  for (const char* method : kMethods) {
    SCOPED_TRACE(method);
    RenderOptions options;
    options.method = method;
    options.spp = 1;
    const Image image = render(h, options);
    EXPECT_TRUE(same_bytes(image, render(a, options)));
    EXPECT_FALSE(same_bytes(image, render(s, options)));
  }
}

TEST(VisibleRender, HiddenMeshIsAbsent) {
  expect_hidden_is_absent("ct-implant.json", 1);  // screw-left, in front of the head
}

TEST(VisibleRender, HiddenPlaneIsAbsent) {
  expect_hidden_is_absent("mpr.json", 2);  // the half-transparent coronal slice
}

}  // namespace
}  // namespace imx
