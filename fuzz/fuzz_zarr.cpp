// Zarr arrays and OME-Zarr images, v2 and v3: the input is an array's metadata (a .zarray's text,
// or a v3 zarr.json's when it names a "node_type"), kDataMarker, then the bytes of one stored
// file: a chunk, or a v3 shard with its index. The file is decoded from memory by the array
// reader, then the harness writes an OME-Zarr folder (NGFF 0.4 or 0.5; axes t, c up to the
// array's rank, then z, y, x) holding that array with the bytes as its first chunk file, read
// through the format registry as a user's folder is.
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
  const bool v3 = parts.head.find("\"node_type\"") != std::string_view::npos;
  imx::detail::ZarrArray array;
  try {
    array = v3 ? imx::detail::parse_zarr_json_array(parts.head, level, "in.zarr/0/zarr.json")
               : imx::detail::parse_zarray(parts.head, level, "in.zarr/0/.zarray");
  } catch (const std::exception& e) {
    refused(e);
    return 0;
  }
  try {
    const auto* stored = reinterpret_cast<const uint8_t*>(parts.tail.data());
    // A few inner chunks of a shard: each may decode to the full chunk size.
    imx::detail::decode_zarr_file(array, {stored, parts.tail.size()}, 8, "chunk");
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
  const std::string multiscales =
      "\"multiscales\": [{\"axes\": [" + axes + "], \"datasets\": [{\"path\": \"0\"}]}]";
  if (v3) {
    dir.write("in.zarr/zarr.json",
              "{\"zarr_format\": 3, \"node_type\": \"group\", \"attributes\": {\"ome\": "
              "{\"version\": \"0.5\", " +
                  multiscales + "}}}");
    dir.write("in.zarr/0/zarr.json", parts.head);
  } else {
    dir.write("in.zarr/.zgroup", std::string_view("{\"zarr_format\": 2}"));
    dir.write("in.zarr/.zattrs", "{" + multiscales + "}");
    dir.write("in.zarr/0/.zarray", parts.head);
  }
  const std::vector<int64_t> first(n, 0);
  const std::filesystem::path chunk = array.chunk_file(first);
  std::filesystem::create_directories(chunk.parent_path());
  dir.write(std::filesystem::relative(chunk, dir.path()).string(), parts.tail);
  fuzz_volume_file(image, size > 0 ? data[size - 1] : 0);
  return 0;
}
