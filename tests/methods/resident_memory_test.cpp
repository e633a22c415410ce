// What a scene's volumes hold resident, as the method that renders them accelerates them.
#include "methods/resident_memory.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "intermix/scene.hpp"
#include "intermix/volume.hpp"

namespace imx {
namespace {

uint64_t bytes_of(const std::vector<ResidentPart>& parts, const std::string& name) {
  for (const ResidentPart& p : parts)
    if (p.name == name) return p.bytes;
  ADD_FAILURE() << "no part named " << name;
  return 0;
}

// One shaded volume alone: mdvr and zSlab's rgba32f slabs march it in lanes and take `auto`
// gradients on the fly; rgba8 slabs, csg and render.gradients=precomputed keep the copy.
TEST(ResidentMemory, GradientCopyOnlyWhereSomeRayMarchesAlone) {
  struct Case {
    const char* method;
    const char* extra;
    bool copy;
  };
  for (const Case& c :
       {Case{"mdvr", "render.packets=true", false},
        Case{"zslab", "render.slab_format=rgba32f", false},
        Case{"zslab-hybrid", "render.slab_format=rgba8", true},
        Case{"csg", "render.mixing=exclusive", true}, Case{"mdvr", "render.packets=false", true},
        Case{"mdvr", "render.gradients=precomputed", true}}) {
    const Scene s = load_scene(std::filesystem::path(IMX_EXAMPLES_DIR) / "ct-head.json",
                               {"objects.ct.source.size=64", c.extra});
    const std::vector<std::vector<ResidentPart>> parts = resident_parts(s, c.method);
    ASSERT_EQ(parts.size(), 1u);
    EXPECT_EQ(bytes_of(parts[0], "voxels"), s.volumes[0].data->voxel_count() * sizeof(int16_t))
        << c.method << " " << c.extra;
    EXPECT_EQ(bytes_of(parts[0], "gradients") > 0, c.copy) << c.method << " " << c.extra;
    EXPECT_GT(bytes_of(parts[0], "pre-integration table"), 0u) << c.method << " " << c.extra;
  }
}

}  // namespace
}  // namespace imx
