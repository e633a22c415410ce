// Zarr v2 arrays and OME-Zarr images: the input is a .zarray's text, kDataMarker, then the bytes
// of one chunk file. The chunk is decoded from memory by the array reader, then the harness
// writes an OME-Zarr folder (axes t, c up to the array's rank, then z, y, x) holding that array
// with the bytes as its first chunk, read through the format registry as a user's folder is.
#include <string>
#include <vector>

#include "harness.hpp"
#include "io/zarr/zarr_array.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace imx::fuzz;
  const ScratchDir& dir = scratch();
  dir.clear();
  const Split parts = split_at(as_view(data, size), kDataMarker);
  const std::filesystem::path image = dir.path() / "in.zarr";
  const std::filesystem::path level = image / "0";
  imx::detail::ZarrArray array;
  try {
    array = imx::detail::parse_zarray(parts.head, level, "in.zarr/0/.zarray");
  } catch (const std::exception& e) {
    refused(e);
    return 0;
  }
  try {
    std::vector<uint8_t> chunk(array.chunk_bytes);
    const auto* stored = reinterpret_cast<const uint8_t*>(parts.tail.data());
    imx::detail::decode_zarr_chunk(array, {stored, parts.tail.size()}, chunk, "chunk");
    accepted("chunk");
  } catch (const std::exception& e) {
    refused(e);
  }
  std::string axes;
  const char* names[] = {"\"t\"", "\"c\"", "\"z\"", "\"y\"", "\"x\""};
  const size_t n = array.shape.size();
  for (size_t d = 0; d < n; ++d)
    axes += std::string(d ? ", " : "") + (n <= 5 ? names[5 - n + d] : "\"q\"");
  std::filesystem::create_directories(level);
  dir.write("in.zarr/.zgroup", std::string_view("{\"zarr_format\": 2}"));
  dir.write("in.zarr/.zattrs", "{\"multiscales\": [{\"version\": \"0.4\", \"axes\": [" + axes +
                                   "], \"datasets\": [{\"path\": \"0\"}]}]}");
  dir.write("in.zarr/0/.zarray", parts.head);
  const std::vector<int64_t> first(n, 0);
  const std::filesystem::path chunk = array.chunk_file(first);
  std::filesystem::create_directories(chunk.parent_path());
  dir.write(std::filesystem::relative(chunk, dir.path()).string(), parts.tail);
  fuzz_volume_file(image, size > 0 ? data[size - 1] : 0);
  return 0;
}
