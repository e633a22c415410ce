#include "io/mesh/mesh_space.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>

#include "io/streams/header_text.hpp"
#include "io/streams/input_file.hpp"

namespace imx {

const char* mesh_space_name(MeshSpace space) {
  return space == MeshSpace::ras ? "RAS" : "LPS";
}

namespace detail {
namespace {

// The first `limit` bytes of the file (fewer when it is shorter).
std::string read_head(const std::filesystem::path& file, size_t limit) {
  std::ifstream in = try_open_input_stream(file);
  std::string out(limit, '\0');
  in.read(out.data(), static_cast<std::streamsize>(limit));
  out.resize(static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return out;
}

// The header of an STL file: 80 bytes when the file's size matches the binary layout
// (80-byte header, triangle count, 50 bytes per triangle), else its first line.
std::string stl_header(const std::filesystem::path& file) {
  std::string head = read_head(file, 1024);
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(file, ec);
  if (!ec && head.size() >= 84) {
    uint32_t count = 0;
    std::memcpy(&count, head.data() + 80, 4);  // little-endian by the format
    if (size == 84 + uintmax_t{50} * count) return head.substr(0, 80);
  }
  return head.substr(0, head.find('\n'));
}

// The comment lines that open an OBJ file (where vtkOBJExporter writes its comment), or those
// of a PLY header ("comment ..." lines up to end_header).
std::string comment_lines(const std::filesystem::path& file, bool ply) {
  const std::string head = read_head(file, kMaxHeaderBytes);
  std::string out;
  size_t pos = 0;
  while (pos < head.size()) {
    size_t eol = std::min(head.find('\n', pos), head.size());
    std::string_view line = trim(std::string_view(head).substr(pos, eol - pos));
    pos = eol + 1;
    if (ply) {
      if (line == "end_header") break;
      if (line.starts_with("comment") || line.starts_with("obj_info")) (out += line) += '\n';
    } else if (line.starts_with("#")) {
      (out += line) += '\n';
    } else if (!line.empty()) {
      break;
    }
  }
  return out;
}

}  // namespace

std::optional<MeshSpace> find_space_tag(std::string_view text) {
  const size_t ras = text.find("SPACE=RAS"), lps = text.find("SPACE=LPS");
  if (ras == std::string_view::npos && lps == std::string_view::npos) return std::nullopt;
  return ras < lps ? MeshSpace::ras : MeshSpace::lps;
}

std::optional<MeshSpace> header_space(const std::filesystem::path& file, std::string_view ext) {
  if (ext == ".stl") return find_space_tag(stl_header(file));
  if (ext == ".obj") return find_space_tag(comment_lines(file, false));
  if (ext == ".ply") return find_space_tag(comment_lines(file, true));
  return std::nullopt;
}

void flip_ras_lps(Mesh& mesh) {
  for (glm::vec3& p : mesh.positions) p = {-p.x, -p.y, p.z};
  for (glm::vec3& n : mesh.normals) n = {-n.x, -n.y, n.z};
}

}  // namespace detail
}  // namespace imx
