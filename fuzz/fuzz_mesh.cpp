// Mesh files through read_mesh: the first byte picks the file extension (kExtensions), the
// rest is the file. read_mesh takes .obj, .stl, .off, .gltf and .glb through assimp (after its
// own checks of glTF, OBJ and OFF), reads .ply by hand and .gii by intermix's own reader (after its
// own check). New extensions go at the end: a seed's first byte keeps its meaning.
#include <exception>
#include <iterator>

#include "harness.hpp"
#include "intermix/io.hpp"

namespace {
constexpr const char* kExtensions[] = {".obj", ".stl", ".off", ".gltf", ".glb", ".ply", ".gii"};
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  if (size < 1) return 0;
  const ScratchDir& dir = scratch();
  dir.clear();
  const char* ext = kExtensions[data[0] % std::size(kExtensions)];
  std::filesystem::path file = dir.write(std::string("in") + ext, data + 1, size - 1);
  try {
    check_mesh(imx::read_mesh(file));
    accepted(ext);
  } catch (const std::exception& e) {
    refused(e);
  }
  return 0;
}
