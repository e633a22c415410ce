// Philips PAR/REC: the PAR text's general information and slice table, read as nibabel.parrec
// reads them (nibabel being the reference the tests compare to).
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"
#include "io/volume/parrec.hpp"
#include "io/volume/parrec_header.hpp"

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
void parse_general(std::string_view line, ParHeader& par, const std::string& what) {
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

ParRow parse_row(std::string_view line, const std::vector<Column>& columns, size_t line_number,
                 const std::string& what) {
  const std::vector<std::string_view> words = split_words(line);
  ParRow row;
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
ParHeader parse_par(const fs::path& file, const std::string& what) {
  require_regular_file(file);
  std::error_code ec;
  const uintmax_t size = fs::file_size(file, ec);
  if (ec) throw FileError(fmt::format("{}: cannot read its size", what), ec.value());
  if (size > kMaxParBytes)
    throw Error(fmt::format("{}: {} bytes is more than a PAR header holds ({} at most)", what, size,
                            kMaxParBytes));
  std::ifstream in = open_input_stream(file, what);
  std::string text(static_cast<size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  text.resize(static_cast<size_t>(in.gcount()));

  enum class State { top, general, comments, table } state = State::top;
  ParHeader par;
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

// nibabel's _truncation_checks: each "Max. number of ..." the general information gives must be
// the number of distinct values in its column, and every volume must hold every slice.
void check_complete(const ParHeader& par, const std::string& what) {
  struct Check {
    const char* name;
    const char* key;
    size_t column;
    const char* column_name;
  };
  const Check checks[] = {
      {"max_slices", "Max. number of slices/locations", ParColumn::kSlice, "slice number"},
      {"max_echoes", "Max. number of echoes", ParColumn::kEcho, "echo number"},
      {"max_dynamics", "Max. number of dynamics", ParColumn::kDynamic, "dynamic scan number"},
      {"max_diffusion_values", "Max. number of diffusion values", ParColumn::kBValueNumber,
       "diffusion b value number"},
      {"max_gradient_orient", "Max. number of gradient orients", ParColumn::kGradientNumber,
       "gradient orientation number"},
  };
  for (const Check& c : checks) {
    const std::vector<double>* expected = par_general(par, c.name);
    if (expected == nullptr) continue;
    if (c.column >= par.rows.front().size())
      throw Error(fmt::format("{}: '{}' is given, but a {} slice table has no '{}' column", what,
                              c.key, par.version, c.column_name));
    std::set<double> values;
    for (const ParRow& row : par.rows) values.insert(row[c.column]);
    if (static_cast<double>(values.size()) != expected->front())
      throw Error(
          fmt::format("{}: header inconsistency: the slice table has {} distinct '{}' "
                      "values, but '{}' is {} (a truncated or inconsistent series)",
                      what, values.size(), c.column_name, c.key, expected->front()));
  }
}

}  // namespace

ParHeader read_par_header(const fs::path& file, const std::string& what) {
  ParHeader par = parse_par(file, what);
  check_complete(par, what);
  return par;
}

const std::vector<double>* par_general(const ParHeader& par, const char* name) {
  auto it = par.numbers.find(name);
  return it == par.numbers.end() ? nullptr : &it->second;
}

const std::vector<double>& require_par_general(const ParHeader& par, const char* name,
                                               const char* key, const std::string& what) {
  const std::vector<double>* v = par_general(par, name);
  if (v == nullptr)
    throw Error(fmt::format("{}: the general information has no '{}' line", what, key));
  return *v;
}

double unique_par_value(const ParHeader& par, size_t index, const char* name,
                        const std::string& what) {
  const double first = par.rows.front()[index];
  for (const ParRow& row : par.rows)
    if (!(row[index] == first) && !(std::isnan(row[index]) && std::isnan(first)))
      throw Error(fmt::format("{}: '{}' varies from slice to slice ({} and {}): not supported",
                              what, name, first, row[index]));
  return first;
}

bool is_parrec_header(std::string_view first_bytes) {
  const std::string_view head = py_strip(first_bytes.substr(0, 256));
  return head.rfind("# === DATA DESCRIPTION FILE", 0) == 0;
}

}  // namespace imx::detail
