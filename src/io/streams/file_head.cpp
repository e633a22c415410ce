#include "io/streams/file_head.hpp"

#include <cerrno>
#include <cstdint>
#include <fstream>
#include <span>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/gzip.hpp"
#include "io/streams/input_file.hpp"

namespace imx::detail {

FileHead read_file_head(const std::filesystem::path& file, size_t size, const std::string& what) {
  std::ifstream in = open_input_stream(file, what);
  FileHead head;
  char magic[2] = {0, 0};
  in.read(magic, 2);
  head.gzipped = in.gcount() == 2 && static_cast<uint8_t>(magic[0]) == 0x1f &&
                 static_cast<uint8_t>(magic[1]) == 0x8b;
  in.clear();
  in.seekg(0);
  head.bytes.resize(size);
  auto* out = reinterpret_cast<uint8_t*>(head.bytes.data());
  size_t got = 0;
  if (head.gzipped) {
    // No finish(): the rest of the stream is the voxels, inflated (and checked) when read.
    GzipStream stream(in, what);
    got = stream.read(std::span<uint8_t>(out, size));
  } else {
    in.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(size));
    got = static_cast<size_t>(in.gcount());
  }
  head.bytes.resize(got);
  return head;
}

}  // namespace imx::detail
