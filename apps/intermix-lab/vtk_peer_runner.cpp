#include "vtk_peer_runner.hpp"

#include <sys/resource.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <variant>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "core/colour.hpp"
#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "io/streams/input_file.hpp"
#include "scene/overrides.hpp"

namespace imx::cli {

namespace {

constexpr const char* kInstallHint = "run scripts/install-deps --with-peers";

// The nearest `start` or ancestor of it holding shared/peers/vtk_peer.py.
std::filesystem::path peer_above(std::filesystem::path start) {
  std::error_code ec;
  start = std::filesystem::weakly_canonical(start, ec);
  if (ec) return {};
  for (std::filesystem::path p = start;; p = p.parent_path()) {
    std::filesystem::path candidate = p / "shared" / "peers" / "vtk_peer.py";
    if (std::filesystem::is_regular_file(candidate, ec)) return candidate;
    if (p == p.root_path() || p.empty()) return {};
  }
}

// A word for /bin/sh: single-quoted, with single quotes spliced in.
std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "/usr/bin:/bin");
  std::string dir;
  std::error_code ec;
  while (std::getline(dirs, dir, ':'))
    if (!dir.empty() && std::filesystem::is_regular_file(std::filesystem::path(dir) / program, ec))
      return true;
  return false;
}

// The system python the peer needs (Debian's python3-vtk9 is built for it), with VTK and NumPy.
constexpr const char* kPython = "/usr/bin/python3";

}  // namespace

void check_vtk_peer(const std::filesystem::path& peer) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(peer, ec))
    throw Error(fmt::format("bench --vtk: no VTK peer at '{}' (give --peer PATH to vtk_peer.py)",
                            peer.string()));
  std::vector<std::string> missing;
  if (!on_path("xvfb-run")) missing.push_back("xvfb-run (package xvfb)");
  if (!std::filesystem::is_regular_file(kPython, ec))
    missing.push_back(kPython);
  else if (std::system(fmt::format("{} -c 'import vtk, numpy' >/dev/null 2>&1", kPython).c_str()) !=
           0)
    missing.push_back("the Python modules vtk and numpy (packages python3-vtk9, python3-numpy)");
  if (!missing.empty())
    throw Error(fmt::format("bench --vtk: the VTK peer needs {}; {}", fmt::join(missing, ", "),
                            kInstallHint));
}

namespace {

// A fresh private folder under the system temp folder, removed with everything in it.
class TempFolder {
 public:
  TempFolder() {
    std::string pattern = (std::filesystem::temp_directory_path() / "intermix-vtk-XXXXXX").string();
    if (!::mkdtemp(pattern.data()))
      throw Error(fmt::format("bench --vtk: cannot create a temporary folder '{}'", pattern));
    path_ = pattern;
  }
  ~TempFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

void write_obj(const Mesh& mesh, const std::filesystem::path& file) {
  fmt::memory_buffer text;
  fmt::format_to(std::back_inserter(text), "# world-space mesh written by intermix bench --vtk\n");
  for (const glm::vec3& p : mesh.positions)
    fmt::format_to(std::back_inserter(text), "v {} {} {}\n", p.x, p.y, p.z);
  for (const glm::uvec3& t : mesh.triangles)
    fmt::format_to(std::back_inserter(text), "f {} {} {}\n", t.x + 1, t.y + 1, t.z + 1);
  std::ofstream out(file, std::ios::binary);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!out) throw Error(fmt::format("{}: writing failed (disk full?)", file.string()));
}

// The last `count` non-empty lines of `text`, for error messages.
std::string last_lines(const std::string& text, size_t count) {
  std::vector<std::string> lines;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(line);
  if (lines.size() > count) lines.erase(lines.begin(), lines.end() - static_cast<long>(count));
  return fmt::format("{}", fmt::join(lines, "\n"));
}

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in = try_open_input_stream(file);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A transfer function's points with alphas per 1 mm of material (VTK's unit distance), in
// display colours as scene files give them (the loader decoded them to linear).
nlohmann::json peer_points(const TransferFunction& tf) {
  nlohmann::json points = nlohmann::json::array();
  for (const TfPoint& p : tf.points) {
    const double alpha =
        1.0 - std::pow(1.0 - std::clamp<double>(p.rgba.a, 0.0, 1.0), 1.0 / tf.unit_distance);
    const glm::vec3 c = linear_to_display(glm::vec3(p.rgba));
    points.push_back({p.value, c.r, c.g, c.b, alpha});
  }
  return points;
}

// The voxels mirrored along i (each row reversed), for a left-handed grid's frame.
void mirror_rows(VolumeData& data) {
  std::visit(
      [&](auto& voxels) {
        auto* values = voxels.mutable_data();
        const size_t row = static_cast<size_t>(data.dims.x);
        for (size_t at = 0; at + row <= voxels.size(); at += row)
          std::reverse(values + at, values + at + row);
      },
      data.voxels);
  data.colours.reset();  // the peer reads scalars only
}

}  // namespace

PeerFrame peer_frame(const glm::dmat4& index_to_world, glm::ivec3 dims) {
  PeerFrame frame;
  glm::dvec3 axis[3];
  for (int a = 0; a < 3; ++a) {
    frame.spacing[a] = glm::length(glm::dvec3(index_to_world[a]));
    if (!(frame.spacing[a] > 0.0)) return frame;
    axis[a] = glm::dvec3(index_to_world[a]) / frame.spacing[a];
  }
  // Axes within 0.006 degrees of square (float affines) count as square.
  constexpr double kSquare = 1e-4;
  for (int a = 0; a < 3; ++a)
    if (std::abs(glm::dot(axis[a], axis[(a + 1) % 3])) > kSquare) return frame;
  glm::dvec3 origin(index_to_world[3]);
  if (glm::dot(glm::cross(axis[0], axis[1]), axis[2]) < 0.0) {
    frame.mirror_i = true;  // index i' = dims.x - 1 - i runs the other way from the far end
    origin += static_cast<double>(dims.x - 1) * frame.spacing.x * axis[0];
    axis[0] = -axis[0];
  }
  const glm::dmat3 to_frame = glm::transpose(glm::dmat3(axis[0], axis[1], axis[2]));
  frame.world_to_frame = glm::dmat4(to_frame);
  frame.world_to_frame[3] = glm::dvec4(-(to_frame * origin), 1.0);
  frame.square = true;
  return frame;
}

std::filesystem::path find_vtk_peer(const std::filesystem::path& scene_file) {
  std::error_code ec;
  std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec)
    if (std::filesystem::path p = peer_above(exe.parent_path()); !p.empty()) return p;
  return peer_above(std::filesystem::absolute(scene_file, ec).parent_path());
}

double peer_sample_distance(const Scene& scene) {
  if (scene.render.step_mm > 0.0) return scene.render.step_mm;
  double pitch = std::numeric_limits<double>::infinity();
  for (const VolumeObject& v : scene.volumes)
    for (int a = 0; a < 3; ++a)
      pitch = std::min(pitch, glm::length(glm::dvec3(v.index_to_world[a])));
  return std::isfinite(pitch) ? pitch : 1.0;
}

std::filesystem::path write_peer_scene(const PeerRun& run, const std::filesystem::path& dir) {
  const std::string origin = run.scene_file.string();
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(read_text(run.scene_file));
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("{}: invalid JSON: {}", origin, e.what()));
  }
  for (const std::string& assignment : run.overrides)
    scene_json::apply_override(root, assignment, origin);

  if (!root.contains("objects") || !root["objects"].is_array())
    throw Error(fmt::format("{}: the scene has no \"objects\" list for the VTK peer", origin));
  // Everything in the first volume's frame, where it has one (PeerFrame).
  // Objects the peer reads from their own files (streamlines) stay in world space, and so
  // then does everything else.
  const bool movable = std::all_of(root["objects"].begin(), root["objects"].end(), [](auto& o) {
    const std::string type = o.value("type", "");
    return type == "volume" || type == "mesh";
  });
  PeerFrame frame;
  if (!run.scene->volumes.empty()) {
    const VolumeObject& first = run.scene->volumes.front();
    const PeerFrame own = peer_frame(first.index_to_world, first.data->dims);
    const bool on_axes =
        own.square && !own.mirror_i && glm::dmat3(own.world_to_frame) == glm::dmat3(1.0);
    if (movable) frame = own;
    if (!frame.square && !on_axes && run.notes)
      std::fprintf(stderr,
                   "intermix-lab: bench --vtk: VTK ignores volume '%s''s direction and draws its "
                   "grid on its own axes (%s)\n",
                   first.name.c_str(),
                   movable ? "a sheared grid: gantry tilt" : "the scene has streamlines");
  }
  const auto to_frame = [&](const glm::dvec3& p) {
    return glm::dvec3(frame.world_to_frame * glm::dvec4(p, 1.0));
  };
  // The camera intermix renders with (a scene without one is framed automatically).
  const Camera& c = run.scene->camera;
  const glm::dvec3 eye = to_frame(c.eye), target = to_frame(c.target);
  const glm::dvec3 up = glm::dmat3(frame.world_to_frame) * c.up;
  root["camera"] = {
      {"eye", {eye.x, eye.y, eye.z}},
      {"target", {target.x, target.y, target.z}},
      {"up", {up.x, up.y, up.z}},
      {"fov_deg", c.fov_deg},
      {"projection", c.projection == Projection::orthographic ? "orthographic" : "perspective"},
      {"ortho_height", c.ortho_height}};
  int written = 0;
  for (nlohmann::json& object : root["objects"]) {
    const std::string name = object.value("name", "");
    const std::string type = object.value("type", "");
    std::filesystem::path file;
    if (type == "volume") {
      auto it = std::find_if(run.scene->volumes.begin(), run.scene->volumes.end(),
                             [&](const VolumeObject& v) { return v.name == name; });
      if (it == run.scene->volumes.end()) continue;
      VolumeData data = *it->data;
      data.index_to_world = frame.world_to_frame * it->index_to_world;  // transform baked in
      if (written == 0 && frame.square) {
        if (frame.mirror_i) mirror_rows(data);
        data.index_to_world = glm::dmat4(1.0);  // on the axes from the origin, as VTK draws it
        for (int a = 0; a < 3; ++a) data.index_to_world[a][a] = frame.spacing[a];
      }
      file = dir / fmt::format("volume-{}.mha", written++);
      write_metaimage(data, file, false);  // uncompressed: quicker to write and to read back
      // The peer reads explicit points only: give it the function intermix resolved (a preset,
      // a colour map, the automatic one, the object's opacity), per millimetre as VTK takes it.
      object["transfer_function"] = {{"points", peer_points(it->transfer_function)}};
    } else if (type == "mesh") {
      auto it = std::find_if(run.scene->meshes.begin(), run.scene->meshes.end(),
                             [&](const MeshObject& m) { return m.name == name; });
      if (it == run.scene->meshes.end()) continue;
      file = dir / fmt::format("mesh-{}.obj", written++);
      Mesh mesh = *it->mesh;
      for (glm::vec3& p : mesh.positions) p = glm::vec3(to_frame(glm::dvec3(p)));
      write_obj(mesh, file);
    } else {
      continue;
    }
    object["source"] = {{"file", file.string()}};
    object.erase("transform");
  }
  std::filesystem::path scene = dir / "scene.json";
  std::ofstream out(scene);
  out << root.dump(2) << "\n";
  if (!out) throw Error(fmt::format("{}: writing failed (disk full?)", scene.string()));
  return scene;
}

PeerTiming run_vtk_peer(const PeerRun& run) {
  TempFolder tmp;
  std::filesystem::path scene = write_peer_scene(run, tmp.path());
  std::filesystem::path log = tmp.path() / "peer.log";
  std::string command = fmt::format(
      "xvfb-run -a -s '-screen 0 1280x1024x24' {} {} {} --mode {} --frames {} --width {} "
      "--height {} --sample-distance {} -o {} 2>{}",
      kPython, quoted(run.peer.string()), quoted(scene.string()), quoted(run.mode), run.frames,
      run.scene->image.width, run.scene->image.height, run.sample_distance_mm,
      quoted((tmp.path() / "vtk.png").string()), quoted(log.string()));

  std::string output;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) throw Error("bench --vtk: cannot start xvfb-run");
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    output.append(buffer.data(), n);
  int status = ::pclose(pipe);
  auto fail = [&](const std::string& why) {
    std::string tail = last_lines(read_text(log) + output, 6);
    return Error(fmt::format("bench --vtk: {} {}{}{}", run.peer.string(), why,
                             tail.empty() ? "" : ":\n", tail));
  };
  if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw fail(
        fmt::format("failed (exit status {})", WIFEXITED(status) ? WEXITSTATUS(status) : -1));

  // The peer prints one JSON object; anything before it is chatter from VTK or Xvfb.
  size_t brace = output.rfind("\n{");
  std::string line = output.substr(brace == std::string::npos ? 0 : brace + 1);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(line);
  } catch (const nlohmann::json::exception&) {
    throw fail("printed no JSON result");
  }
  if (!j.contains("ms_median") || !j["ms_median"].is_number()) throw fail("gave no ms_median");
  PeerTiming t;
  t.ms_median = j["ms_median"].get<double>();
  t.ms_min = j.value("ms_min", t.ms_median);
  t.ms_max = j.value("ms_max", t.ms_median);
  t.empty_image = j.value("empty_image", false);
  if (j.contains("load_ms") && j.contains("first_frame_ms") && j["load_ms"].is_number() &&
      j["first_frame_ms"].is_number())
    t.first_image_ms = j["load_ms"].get<double>() + j["first_frame_ms"].get<double>();
  rusage usage{};
  getrusage(RUSAGE_CHILDREN, &usage);  // the largest finished child: python or Xvfb
  t.peak_rss_mib = static_cast<double>(usage.ru_maxrss) / 1024.0;
  return t;
}

}  // namespace imx::cli
