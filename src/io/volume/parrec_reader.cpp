// Philips PAR/REC, read as nibabel.parrec reads it (nibabel being the reference the tests compare
// to): the PAR text's general information and slice table, the REC's little-endian unsigned
// 8- or 16-bit slices in table order.
#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/frame_voxels.hpp"
#include "io/frames.hpp"
#include "io/header_text.hpp"
#include "io/raw_voxels.hpp"
#include "io/regular_file.hpp"
#include "io/volume/parrec.hpp"
#include "volume/volume_checks.hpp"

namespace imx::detail {

namespace {

namespace fs = std::filesystem;

// Real PAR files are tens to hundreds of kB (a line per slice); more is not a PAR header.
constexpr uintmax_t kMaxParBytes = uintmax_t{64} << 20;

enum class Kind : uint8_t { text, integer, real };

// A "General Information" line's key, the name the reader keeps it under (two spellings seen in
// the wild share one name), its kind and how many numbers it holds (0: any number).
struct GeneralField {
  const char* key;
  const char* name;
  Kind kind;
  int count;
};

// The keys nibabel knows; it refuses any other (a format variant it has not seen).
constexpr GeneralField kGeneralFields[] = {
    {"Patient name", "patient_name", Kind::text, 1},
    {"Examination name", "exam_name", Kind::text, 1},
    {"Protocol name", "protocol_name", Kind::text, 1},
    {"Examination date/time", "exam_date", Kind::text, 1},
    {"Series Type", "series_type", Kind::text, 1},
    {"Acquisition nr", "acq_nr", Kind::integer, 1},
    {"Reconstruction nr", "recon_nr", Kind::integer, 1},
    {"Scan Duration [sec]", "scan_duration", Kind::real, 1},
    {"Max. number of cardiac phases", "max_cardiac_phases", Kind::integer, 1},
    {"Max. number of echoes", "max_echoes", Kind::integer, 1},
    {"Max. number of slices/locations", "max_slices", Kind::integer, 1},
    {"Max. number of dynamics", "max_dynamics", Kind::integer, 1},
    {"Max. number of mixes", "max_mixes", Kind::integer, 1},
    {"Patient position", "patient_position", Kind::text, 1},
    {"Preparation direction", "prep_direction", Kind::text, 1},
    {"Technique", "tech", Kind::text, 1},
    {"Scan resolution  (x, y)", "scan_resolution", Kind::integer, 2},
    {"Scan mode", "scan_mode", Kind::text, 1},
    {"Repetition time [ms]", "repetition_time", Kind::real, 0},
    {"FOV (ap,fh,rl) [mm]", "fov", Kind::real, 3},
    {"Water Fat shift [pixels]", "water_fat_shift", Kind::real, 1},
    {"Angulation midslice(ap,fh,rl)[degr]", "angulation", Kind::real, 3},
    {"Off Centre midslice(ap,fh,rl) [mm]", "off_center", Kind::real, 3},
    {"Flow compensation <0=no 1=yes> ?", "flow_compensation", Kind::integer, 1},
    {"Presaturation     <0=no 1=yes> ?", "presaturation", Kind::integer, 1},
    {"Phase encoding velocity [cm/sec]", "phase_enc_velocity", Kind::real, 3},
    {"MTC               <0=no 1=yes> ?", "mtc", Kind::integer, 1},
    {"SPIR              <0=no 1=yes> ?", "spir", Kind::integer, 1},
    {"EPI factor        <0,1=no EPI>", "epi_factor", Kind::integer, 1},
    {"Dynamic scan      <0=no 1=yes> ?", "dyn_scan", Kind::integer, 1},
    {"Diffusion         <0=no 1=yes> ?", "diffusion", Kind::integer, 1},
    {"Diffusion echo time [ms]", "diffusion_echo_time", Kind::real, 1},
    {"Max. number of diffusion values", "max_diffusion_values", Kind::integer, 1},
    {"Max. number of gradient orients", "max_gradient_orient", Kind::integer, 1},
    {"Number of label types   <0=no ASL>", "nr_label_types", Kind::integer, 1},
    {"Series_data_type", "series_type", Kind::text, 1},
    {"Patient Position", "patient_position", Kind::text, 1},
    {"Repetition time [msec]", "repetition_time", Kind::real, 0},
    {"Diffusion echo time [msec]", "diffusion_echo_time", Kind::real, 1},
};

// The slice table's columns, in order, for version 4; 4.1 and 4.2 append theirs.
struct Column {
  const char* name;
  Kind kind;
  int count;
};
constexpr Column kColumnsV4[] = {
    {"slice number", Kind::integer, 1},
    {"echo number", Kind::integer, 1},
    {"dynamic scan number", Kind::integer, 1},
    {"cardiac phase number", Kind::integer, 1},
    {"image type", Kind::integer, 1},
    {"scanning sequence", Kind::integer, 1},
    {"index in REC file", Kind::integer, 1},
    {"image pixel size", Kind::integer, 1},
    {"scan percentage", Kind::integer, 1},
    {"recon resolution", Kind::integer, 2},
    {"rescale intercept", Kind::real, 1},
    {"rescale slope", Kind::real, 1},
    {"scale slope", Kind::real, 1},
    {"window center", Kind::real, 1},
    {"window width", Kind::real, 1},
    {"image angulation", Kind::real, 3},
    {"image offcentre", Kind::real, 3},
    {"slice thickness", Kind::real, 1},
    {"slice gap", Kind::real, 1},
    {"image display orientation", Kind::integer, 1},
    {"slice orientation", Kind::integer, 1},
    {"fmri status indication", Kind::integer, 1},
    {"image type ed es", Kind::integer, 1},
    {"pixel spacing", Kind::real, 2},
    {"echo time", Kind::real, 1},
    {"dyn scan begin time", Kind::real, 1},
    {"trigger time", Kind::real, 1},
    {"diffusion b factor", Kind::real, 1},
    {"number of averages", Kind::integer, 1},
    {"image flip angle", Kind::real, 1},
    {"cardiac frequency", Kind::integer, 1},
    {"minimum RR-interval", Kind::integer, 1},
    {"maximum RR-interval", Kind::integer, 1},
    {"TURBO factor", Kind::integer, 1},
    {"Inversion delay", Kind::real, 1},
};
constexpr Column kColumnsV41[] = {
    {"diffusion b value number", Kind::integer, 1},
    {"gradient orientation number", Kind::integer, 1},
    {"contrast type", Kind::text, 1},
    {"diffusion anisotropy type", Kind::text, 1},
    {"diffusion", Kind::real, 3},
};
constexpr Column kColumnsV42[] = {{"label type", Kind::integer, 1}};

// Where the values the reader uses sit in a parsed row (one value per number, text as 0).
enum Value : size_t {
  kSlice = 0,
  kEcho = 1,
  kDynamic = 2,
  kImageType = 4,
  kPixelBits = 7,
  kReconX = 9,
  kReconY = 10,
  kRescaleIntercept = 11,
  kRescaleSlope = 12,
  kThickness = 22,
  kGap = 23,
  kOrientation = 25,
  kSpacingX = 28,
  kSpacingY = 29,
  kEchoTime = 30,
  kDynamicStart = 31,
  kTriggerTime = 32,
  kBFactor = 33,
  kBValueNumber = 41,  // 4.1 on
  kGradientNumber = 42,
  kGradient = 45,  // ap, fh, rl
};

using Row = std::vector<double>;

struct Par {
  std::string version;                                 // "V4", "V4.1", "V4.2"
  std::map<std::string, std::vector<double>> numbers;  // general information, by name
  std::vector<Row> rows;                               // the slice table, in file order
};

// Python's str.strip(): the reference reader strips every line before looking at it.
std::string_view py_strip(std::string_view s) {
  auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  while (!s.empty() && space(s.front())) s.remove_prefix(1);
  while (!s.empty() && space(s.back())) s.remove_suffix(1);
  return s;
}

std::optional<double> parse_number(std::string_view word, Kind kind) {
  if (kind == Kind::integer) {
    const std::optional<int64_t> v = parse_header_number<int64_t>(word);
    if (!v || std::abs(*v) > (int64_t{1} << 53)) return std::nullopt;
    return static_cast<double>(*v);
  }
  return parse_header_number<double>(word);
}

std::vector<std::string_view> lines_of(std::string_view text) {
  std::vector<std::string_view> lines;
  size_t start = 0;
  for (size_t i = 0; i <= text.size(); ++i)
    if (i == text.size() || text[i] == '\n' || text[i] == '\r') {
      lines.push_back(text.substr(start, i - start));
      start = i + 1;
    }
  return lines;
}

// A "General Information" line: '.', blanks, the key up to the first ':', the value after it.
void parse_general(std::string_view line, Par& par, const std::string& what) {
  const auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  const size_t colon = line.find(':');
  if (line.size() < 2 || !space(line[1]) || colon == std::string_view::npos)
    throw Error(
        fmt::format("{}: general information line '{}' is not '. key : value'", what, shown(line)));
  std::string_view key = line.substr(1, colon - 1);
  while (!key.empty() && space(key.front())) key.remove_prefix(1);
  while (!key.empty() && space(key.back())) key.remove_suffix(1);
  const std::string_view value = py_strip(line.substr(colon + 1));
  const GeneralField* field = nullptr;
  for (const GeneralField& f : kGeneralFields)
    if (key == f.key) field = &f;
  if (field == nullptr)
    throw Error(fmt::format("{}: general information field '{}' is not one nibabel knows", what,
                            shown(key)));
  if (field->kind == Kind::text) return;
  const std::vector<std::string_view> words = split_words(value);
  std::vector<double> numbers;
  for (std::string_view w : words) {
    const std::optional<double> v = parse_number(w, field->kind);
    if (!v)
      throw Error(fmt::format("{}: general information field '{}' holds '{}', not {}", what, key,
                              shown(value), field->kind == Kind::integer ? "integers" : "numbers"));
    numbers.push_back(*v);
  }
  if (field->count != 0 && static_cast<int>(numbers.size()) != field->count)
    throw Error(fmt::format("{}: general information field '{}' holds {} numbers, not {}", what,
                            key, numbers.size(), field->count));
  par.numbers[field->name] = std::move(numbers);
}

std::vector<Column> columns_of(const std::string& version) {
  std::vector<Column> columns(std::begin(kColumnsV4), std::end(kColumnsV4));
  if (version == "V4.1" || version == "V4.2")
    columns.insert(columns.end(), std::begin(kColumnsV41), std::end(kColumnsV41));
  if (version == "V4.2")
    columns.insert(columns.end(), std::begin(kColumnsV42), std::end(kColumnsV42));
  return columns;
}

Row parse_row(std::string_view line, const std::vector<Column>& columns, size_t line_number,
              const std::string& what) {
  const std::vector<std::string_view> words = split_words(line);
  Row row;
  size_t word = 0;
  for (const Column& c : columns)
    for (int n = 0; n < c.count; ++n, ++word) {
      if (word >= words.size())
        throw Error(fmt::format("{}: line {} of the slice table ends before its '{}' column", what,
                                line_number, c.name));
      if (c.kind == Kind::text) {
        row.push_back(0.0);
        continue;
      }
      const std::optional<double> v = parse_number(words[word], c.kind);
      if (!v)
        throw Error(fmt::format("{}: line {}, column '{}' is '{}', not {}", what, line_number,
                                c.name, shown(words[word]),
                                c.kind == Kind::integer ? "an integer" : "a number"));
      row.push_back(*v);
    }
  return row;
}

// The PAR text as nibabel's _split_header walks it: comment lines (one naming the export tool's
// version), '.' lines of general information, more comments, then a table line per slice up to
// the next comment.
Par parse_par(const fs::path& file, const std::string& what) {
  require_regular_file(file);
  std::error_code ec;
  const uintmax_t size = fs::file_size(file, ec);
  if (ec) throw FileError(fmt::format("{}: cannot read its size", what), ec.value());
  if (size > kMaxParBytes)
    throw Error(fmt::format("{}: {} bytes is more than a PAR header holds ({} at most)", what, size,
                            kMaxParBytes));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw FileError(fmt::format("{}: cannot open file", what), errno);
  std::string text(static_cast<size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  text.resize(static_cast<size_t>(in.gcount()));

  enum class State { top, general, comments, table } state = State::top;
  Par par;
  bool have_version = false;
  std::vector<std::pair<size_t, std::string_view>> table;
  size_t line_number = 0;
  for (std::string_view raw : lines_of(text)) {
    ++line_number;
    const std::string_view line = py_strip(raw);
    if (line.empty()) continue;
    const bool comment = line.front() == '#';
    if (state == State::top) {
      if (!comment) {
        state = State::general;
      } else if (line.find("image export tool") != std::string_view::npos) {
        const std::vector<std::string_view> words = split_words(line);
        par.version = std::string(words.back());
        have_version = true;
      }
    }
    if (state == State::general) {
      if (line.front() != '.')
        state = State::comments;
      else
        parse_general(line, par, what);
    }
    if (state == State::comments && !comment) state = State::table;
    if (state == State::table) {
      if (comment) break;
      table.emplace_back(line_number, line);
    }
  }
  if (!have_version)
    throw Error(
        fmt::format("{}: no 'image export tool' line gives the PAR version: not a PAR "
                    "header, or one nibabel does not read",
                    what));
  if (par.version != "V4" && par.version != "V4.1" && par.version != "V4.2")
    throw Error(fmt::format("{}: PAR version '{}' is not supported (V4, V4.1 and V4.2 are)", what,
                            shown(par.version)));
  const std::vector<Column> columns = columns_of(par.version);
  par.rows.reserve(table.size());
  for (const auto& [number, line] : table)
    par.rows.push_back(parse_row(line, columns, number, what));
  if (par.rows.empty()) throw Error(fmt::format("{}: the slice table has no lines", what));
  return par;
}

const std::vector<double>* general(const Par& par, const char* name) {
  auto it = par.numbers.find(name);
  return it == par.numbers.end() ? nullptr : &it->second;
}

const std::vector<double>& require_general(const Par& par, const char* name, const char* key,
                                           const std::string& what) {
  const std::vector<double>* v = general(par, name);
  if (v == nullptr)
    throw Error(fmt::format("{}: the general information has no '{}' line", what, key));
  return *v;
}

// The one value column `index` holds on every line (nibabel refuses a property that varies).
double unique_value(const Par& par, size_t index, const char* name, const std::string& what) {
  const double first = par.rows.front()[index];
  for (const Row& row : par.rows)
    if (!(row[index] == first) && !(std::isnan(row[index]) && std::isnan(first)))
      throw Error(fmt::format("{}: '{}' varies from slice to slice ({} and {}): not supported",
                              what, name, first, row[index]));
  return first;
}

struct Layout {
  VolumeHeader header;
  fs::path rec;
  std::string rec_what;
  int bytes_per_pixel = 2;
  std::vector<size_t> order;             // table line of each (volume, slice), slice fastest
  std::vector<double> slope, intercept;  // per table line
};

// nibabel's _truncation_checks: each "Max. number of ..." the general information gives must be
// the number of distinct values in its column, and every volume must hold every slice.
void check_complete(const Par& par, const std::string& what) {
  struct Check {
    const char* name;
    const char* key;
    size_t column;
    const char* column_name;
  };
  const Check checks[] = {
      {"max_slices", "Max. number of slices/locations", kSlice, "slice number"},
      {"max_echoes", "Max. number of echoes", kEcho, "echo number"},
      {"max_dynamics", "Max. number of dynamics", kDynamic, "dynamic scan number"},
      {"max_diffusion_values", "Max. number of diffusion values", kBValueNumber,
       "diffusion b value number"},
      {"max_gradient_orient", "Max. number of gradient orients", kGradientNumber,
       "gradient orientation number"},
  };
  for (const Check& c : checks) {
    const std::vector<double>* expected = general(par, c.name);
    if (expected == nullptr) continue;
    if (c.column >= par.rows.front().size())
      throw Error(fmt::format("{}: '{}' is given, but a {} slice table has no '{}' column", what,
                              c.key, par.version, c.column_name));
    std::set<double> values;
    for (const Row& row : par.rows) values.insert(row[c.column]);
    if (static_cast<double>(values.size()) != expected->front())
      throw Error(
          fmt::format("{}: header inconsistency: the slice table has {} distinct '{}' "
                      "values, but '{}' is {} (a truncated or inconsistent series)",
                      what, values.size(), c.column_name, c.key, expected->front()));
  }
}

// PSL (Philips' patient axes) of the voxel axes for each slice orientation (1 transverse,
// 2 sagittal, 3 coronal), as nibabel's ACQ_TO_PSL: rows P, S, L; columns i, j, k.
glm::dmat3 to_psl(int orientation) {
  glm::dmat3 m(0.0);  // m[column][row]
  auto set = [&](int row, int column, double v) { m[column][row] = v; };
  if (orientation == 1) {
    set(0, 1, 1);
    set(1, 2, 1);
    set(2, 0, 1);
  } else if (orientation == 2) {
    set(0, 0, 1);
    set(1, 1, -1);
    set(2, 2, -1);
  } else {
    set(0, 2, 1);
    set(1, 1, -1);
    set(2, 0, 1);
  }
  return m;
}

glm::dmat3 rotation(int axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  glm::dmat3 m(1.0);  // m[column][row]
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  m[a][a] = c;
  m[b][a] = -s;
  m[a][b] = s;
  m[b][b] = c;
  return m;
}

// nibabel's PARRECHeader.get_affine(origin='scanner'): centre the grid, scale by the voxel sizes,
// permute to PSL, rotate by the angulation (Rz(rl) Rx(ap) Ry(fh), nibabel's order), move by the
// off-centre; then PSL -> LPS (L = PSL's third, P its first, S its second).
glm::dmat4 index_to_lps(glm::ivec3 dims, glm::dvec3 zooms, int orientation,
                        const std::vector<double>& angulation,
                        const std::vector<double>& off_centre) {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  const glm::dmat3 rot = rotation(2, angulation[2] * kDeg) * rotation(0, angulation[0] * kDeg) *
                         rotation(1, angulation[1] * kDeg);
  glm::dmat3 scale(1.0);
  for (int a = 0; a < 3; ++a) scale[a][a] = zooms[a];
  const glm::dmat3 psl = rot * to_psl(orientation) * scale;
  const glm::dvec3 centre = (glm::dvec3(dims) - 1.0) / 2.0;
  const glm::dvec3 origin =
      -(psl * centre) + glm::dvec3(off_centre[0], off_centre[1], off_centre[2]);
  glm::dmat4 lps(1.0);
  for (int c = 0; c < 3; ++c) {
    lps[c][0] = psl[c][2];
    lps[c][1] = psl[c][0];
    lps[c][2] = psl[c][1];
  }
  lps[3] = glm::dvec4(origin[2], origin[0], origin[1], 1.0);
  return lps;
}

// The other file of the pair: the same name with `ext` in the given extension's case, else in
// the other case.
fs::path partner(const fs::path& file, const char* upper, const char* lowercase) {
  const std::string given = file.extension().string();
  const bool is_upper =
      std::any_of(given.begin(), given.end(), [](unsigned char c) { return std::isupper(c) != 0; });
  fs::path first = file, second = file;
  first.replace_extension(is_upper ? upper : lowercase);
  second.replace_extension(is_upper ? lowercase : upper);
  std::error_code ec;
  if (fs::exists(first, ec) || !fs::exists(second, ec)) return first;
  return second;
}

// Frame labels: for each volume, what its first slice's line says, for the properties that
// differ between volumes (b values and directions for a diffusion series, as nibabel's
// get_bvals_bvecs gives them: along the voxel axes).
void label_frames(const Par& par, Layout& l, int orientation, int slices) {
  const int frames = l.header.frames;
  if (frames < 2) return;
  auto first_row = [&](int f) -> const Row& {
    return par.rows[l.order[static_cast<size_t>(f) * slices]];
  };
  auto varies = [&](size_t column) {
    for (int f = 1; f < frames; ++f)
      if (first_row(f)[column] != first_row(0)[column]) return true;
    return false;
  };
  const std::vector<double>* diffusion = general(par, "diffusion");
  const bool dwi = diffusion != nullptr && diffusion->front() != 0.0;
  const bool has_gradient = par.rows.front().size() > kGradient + 2;
  const bool time = varies(kDynamicStart), echo = varies(kEchoTime), trigger = varies(kTriggerTime),
             type = varies(kImageType);
  if (!dwi && !time && !echo && !trigger && !type) return;
  const glm::dmat3 psl = to_psl(orientation);
  l.header.frame_labels.resize(static_cast<size_t>(frames));
  for (int f = 0; f < frames; ++f) {
    const Row& row = first_row(f);
    FrameLabel& label = l.header.frame_labels[static_cast<size_t>(f)];
    if (time) label.time_s = row[kDynamicStart] - first_row(0)[kDynamicStart];
    if (dwi) {
      label.b_value = row[kBFactor];
      // The table's (ap, fh, rl) read as PSL, taken back to the voxel axes.
      if (has_gradient)
        label.b_vector = glm::transpose(psl) *
                         glm::dvec3(row[kGradient], row[kGradient + 1], row[kGradient + 2]);
    }
    if (echo) label.echo_time_ms = row[kEchoTime];
    if (trigger) label.trigger_time_ms = row[kTriggerTime];
    if (type) {
      static const char* const kTypes[] = {"M", "R", "I", "P"};
      const double t = row[kImageType];
      label.image_type = t >= 0 && t < 4 ? kTypes[static_cast<int>(t)] : fmt::format("type {}", t);
    }
    label.text = describe_frame(label);
  }
}

Layout parse_layout(const fs::path& file) {
  const std::string given = file.string();
  const std::string ext = lower(file.extension().string());
  fs::path par_file, rec_file;
  if (ext == ".par") {
    par_file = file;
    rec_file = partner(file, ".REC", ".rec");
  } else if (ext == ".rec") {
    rec_file = file;
    par_file = partner(file, ".PAR", ".par");
  } else {
    throw Error(fmt::format("{}: a PAR/REC file must be named .PAR or .REC", given));
  }
  const std::string what = par_file.string();
  const Par par = parse_par(par_file, what);
  check_complete(par, what);

  // nibabel's vol_numbers and vol_is_full: the n-th line of a slice number belongs to volume n,
  // and every volume must hold each slice 1 .. max_slices.
  const double max_slices =
      require_general(par, "max_slices", "Max. number of slices/locations", what).front();
  if (max_slices < 1 || max_slices > static_cast<double>(par.rows.size()))
    throw Error(fmt::format("{}: 'Max. number of slices/locations' is {} for a table of {} lines",
                            what, max_slices, par.rows.size()));
  const int slices = static_cast<int>(max_slices);
  std::vector<std::vector<size_t>> lines_of_slice(static_cast<size_t>(slices));
  for (size_t r = 0; r < par.rows.size(); ++r) {
    const double s = par.rows[r][kSlice];
    if (s < 1 || s > slices)
      throw Error(fmt::format("{}: line {} of the slice table has slice number {}, outside 1 .. {}",
                              what, r + 1, s, slices));
    lines_of_slice[static_cast<size_t>(s) - 1].push_back(r);
  }
  const size_t volumes = lines_of_slice.front().size();
  for (int s = 0; s < slices; ++s)
    if (lines_of_slice[static_cast<size_t>(s)].size() != volumes)
      throw Error(
          fmt::format("{}: slice {} appears {} times and slice 1 {} times: the series has "
                      "one or more partial volumes",
                      what, s + 1, lines_of_slice[static_cast<size_t>(s)].size(), volumes));
  if (static_cast<int64_t>(volumes) > kMaxFrames)
    throw Error(fmt::format("{}: {} volumes is more than {}", what, volumes, kMaxFrames));

  Layout l;
  const double bits = unique_value(par, kPixelBits, "image pixel size", what);
  if (bits != 8 && bits != 16)
    throw Error(
        fmt::format("{}: image pixel size is {} bits: only 8 and 16 are supported", what, bits));
  l.bytes_per_pixel = bits == 8 ? 1 : 2;
  const double rx = unique_value(par, kReconX, "recon resolution", what);
  const double ry = unique_value(par, kReconY, "recon resolution", what);
  if (rx < 1 || ry < 1 || rx * ry * slices > static_cast<double>(kMaxVoxels))
    throw Error(fmt::format("{}: recon resolution {} x {} with {} slices is not a valid grid", what,
                            rx, ry, slices));
  const glm::ivec3 dims(static_cast<int>(rx), static_cast<int>(ry), slices);
  check_frame_count(dims, static_cast<int64_t>(volumes), what);
  const double gap = unique_value(par, kGap, "slice gap", what);
  const double sx = unique_value(par, kSpacingX, "pixel spacing", what);
  const double sy = unique_value(par, kSpacingY, "pixel spacing", what);
  const double thickness = unique_value(par, kThickness, "slice thickness", what);
  if (volumes > 1) {
    // nibabel reads the TR for a dynamic series' fourth zoom, and refuses a header without it.
    const double dynamic = require_general(par, "dyn_scan", "Dynamic scan", what).front();
    if (dynamic != 0 &&
        require_general(par, "repetition_time", "Repetition time [ms]", what).empty())
      throw Error(fmt::format("{}: 'Repetition time' holds no number", what));
  }

  // The REC holds every line's slice in table order, whatever the table's "index in REC file".
  l.rec = rec_file;
  l.rec_what = fmt::format("{} (REC data of {})", rec_file.string(), what);
  require_regular_file(rec_file, l.rec_what);
  std::error_code ec;
  const uintmax_t rec_size = fs::file_size(rec_file, ec);
  if (ec) throw FileError(fmt::format("{}: cannot read its size", l.rec_what), ec.value());
  const uintmax_t needed = static_cast<uintmax_t>(rx) * static_cast<uintmax_t>(ry) *
                           par.rows.size() * static_cast<uintmax_t>(l.bytes_per_pixel);
  if (rec_size < needed)
    throw Error(
        fmt::format("{}: holds {} bytes, but the PAR's {} slices of {} x {} {}-bit pixels "
                    "need {}",
                    l.rec_what, rec_size, par.rows.size(), rx, ry, bits, needed));

  const double orientation = unique_value(par, kOrientation, "slice orientation", what);
  if (orientation != 1 && orientation != 2 && orientation != 3)
    throw Error(
        fmt::format("{}: slice orientation {} is not 1 (transverse), 2 (sagittal) or 3 "
                    "(coronal)",
                    what, orientation));
  const std::vector<double>& angulation =
      require_general(par, "angulation", "Angulation midslice(ap,fh,rl)[degr]", what);
  const std::vector<double>& off_centre =
      require_general(par, "off_center", "Off Centre midslice(ap,fh,rl) [mm]", what);

  l.order.reserve(volumes * static_cast<size_t>(slices));
  for (size_t v = 0; v < volumes; ++v)
    for (int s = 0; s < slices; ++s) l.order.push_back(lines_of_slice[static_cast<size_t>(s)][v]);
  for (const Row& row : par.rows) {
    l.slope.push_back(row[kRescaleSlope]);
    l.intercept.push_back(row[kRescaleIntercept]);
  }
  l.header.dims = dims;
  l.header.type = VoxelType::f32;
  l.header.frames = static_cast<int>(volumes);
  l.header.index_to_world = index_to_lps(dims, glm::dvec3(sx, sy, thickness + gap),
                                         static_cast<int>(orientation), angulation, off_centre);
  label_frames(par, l, static_cast<int>(orientation), slices);
  return l;
}

// The box of frame `frame`, slice by slice: each slice's rows of the box in one read, scaled by
// that slice's rescale slope and intercept.
VoxelStorage read_box(const Layout& l, int frame, const VoxelBox& box) {
  const glm::ivec3 dims = l.header.dims, size = box.size();
  std::ifstream in(l.rec, std::ios::binary);
  if (!in) throw FileError(fmt::format("{}: cannot open file", l.rec_what), errno);
  const uint64_t slice_bytes = static_cast<uint64_t>(dims.x) * dims.y * l.bytes_per_pixel;
  const size_t row_bytes = static_cast<size_t>(dims.x) * l.bytes_per_pixel;
  std::vector<uint8_t> rows(row_bytes * static_cast<size_t>(size.y));
  return load_voxels(RawType::f32, box.count(), false, l.rec_what, [&](std::span<uint8_t> out) {
    float* voxels = reinterpret_cast<float*>(out.data());
    for (int k = box.lo.z; k < box.hi.z; ++k) {
      const size_t line = l.order[static_cast<size_t>(frame) * dims.z + k];
      in.seekg(static_cast<std::streamoff>(line * slice_bytes + box.lo.y * row_bytes));
      in.read(reinterpret_cast<char*>(rows.data()), static_cast<std::streamsize>(rows.size()));
      if (!in)
        throw Error(fmt::format("{}: ends within slice {} (the file shrank while read)", l.rec_what,
                                line + 1));
      const double slope = l.slope[line], intercept = l.intercept[line];
      for (int j = 0; j < size.y; ++j)
        for (int i = 0; i < size.x; ++i) {
          const size_t at = static_cast<size_t>(j) * dims.x + box.lo.x + i;
          const double raw = l.bytes_per_pixel == 1
                                 ? rows[at]
                                 : static_cast<double>(rows[2 * at] | (rows[2 * at + 1] << 8));
          *voxels++ = static_cast<float>(raw * slope + intercept);
        }
    }
  });
}

}  // namespace

bool is_parrec_header(std::string_view first_bytes) {
  const std::string_view head = py_strip(first_bytes.substr(0, 256));
  return head.rfind("# === DATA DESCRIPTION FILE", 0) == 0;
}

VolumeHeader read_parrec_header(const std::filesystem::path& file) {
  VolumeHeader header = parse_layout(file).header;
  check_placement(header.index_to_world, file.string());
  return header;
}

VolumeData read_parrec_region(const std::filesystem::path& file, const VoxelBox& box, int frame) {
  const Layout l = parse_layout(file);
  require_frame(frame, l.header.frames, file.string());
  require_box_inside(l.header.dims, box, file.string());
  VolumeData v;
  v.dims = box.size();
  v.index_to_world = box_index_to_world(l.header.index_to_world, box.lo);
  v.voxels = read_box(l, frame, box);
  v.validate(file.string());
  return v;
}

VolumeData read_parrec(const std::filesystem::path& file, int frame) {
  const Layout l = parse_layout(file);
  require_frame(frame, l.header.frames, file.string());
  VolumeData v;
  v.dims = l.header.dims;
  v.index_to_world = l.header.index_to_world;
  v.voxels = read_box(l, frame, VoxelBox::whole(v.dims));
  v.validate(file.string());
  return v;
}

}  // namespace imx::detail
