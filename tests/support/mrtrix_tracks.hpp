// Writes MRtrix track files (.tck, and .tsf values) for tests: records of float32 per point,
// each ended by a NaN separator, the file by an inf marker, as MRtrix writes them.
#pragma once
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace imx::test {

// `magic` is "mrtrix tracks" or "mrtrix track scalars"; each record holds `per_point` floats per
// point (3 for positions, 1 for values).
inline void write_mrtrix_tracks(const std::filesystem::path& file, const char* magic,
                                const std::vector<std::vector<float>>& records, int per_point) {
  std::string header =
      fmt::format("{}\ndatatype: Float32LE\ncount: {}\nfile: . ", magic, records.size());
  const size_t offset = header.size() + 16;
  header += fmt::format("{}\nEND\n", offset);
  header.resize(offset, '\0');
  std::ofstream out(file, std::ios::binary);
  out << header;
  const float nan = std::nanf(""), inf = INFINITY;
  for (const auto& r : records) {
    out.write(reinterpret_cast<const char*>(r.data()), static_cast<std::streamsize>(r.size() * 4));
    for (int c = 0; c < per_point; ++c) out.write(reinterpret_cast<const char*>(&nan), 4);
  }
  for (int c = 0; c < per_point; ++c) out.write(reinterpret_cast<const char*>(&inf), 4);
}

}  // namespace imx::test
