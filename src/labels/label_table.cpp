// read_label_table: a colour-table file by its content; the checks and palette every table shares.
#include <algorithm>
#include <cerrno>
#include <fstream>
#include <unordered_map>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/io.hpp"
#include "intermix/labels.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"
#include "labels/colour_table_readers.hpp"
#include "labels/label_table_formats.hpp"
#include "labels/label_text.hpp"

namespace imx {
namespace {

// FreeSurferColorLUT.txt, the largest table in use, is about 1 MB.
constexpr size_t kMaxTableBytes = size_t{16} << 20;
// A NRRD header, key/value fields included: Slicer's hold kilobytes per segment.
constexpr size_t kMaxNrrdHeaderBytes = size_t{4} << 20;

// The file's first `limit` bytes; with `whole`, an error when it is longer.
std::string read_head(const std::filesystem::path& file, size_t limit, bool whole) {
  require_regular_file(file);
  std::ifstream in = open_input_stream(file, file.string());
  std::string text(limit + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw Error(fmt::format("{}: reading failed", file.string()));
  text.resize(static_cast<size_t>(in.gcount()));
  if (text.size() > limit) {
    if (whole)
      throw Error(fmt::format("{}: larger than the {} bytes a colour table may have", file.string(),
                              limit));
    text.resize(limit);
  }
  return text;
}

// The first line that is neither blank nor a comment.
std::string_view first_row(std::string_view text) {
  for (std::string_view l : labels_detail::lines(text))
    if (!labels_detail::skippable(l)) return l;
  return {};
}

}  // namespace

void validate_label_entries(const std::vector<LabelEntry>& entries, const std::string& what) {
  std::unordered_map<int32_t, size_t> seen;
  for (size_t i = 0; i < entries.size(); ++i) {
    const LabelEntry& e = entries[i];
    if (e.value < -labels_detail::kMaxLabelMagnitude || e.value > labels_detail::kMaxLabelMagnitude)
      throw Error(fmt::format("{}: label {} is beyond +-{}", what, e.value,
                              labels_detail::kMaxLabelMagnitude));
    auto [it, fresh] = seen.emplace(e.value, i);
    if (!fresh)
      throw Error(fmt::format("{}: label {} is listed twice ('{}' and '{}')", what, e.value,
                              entries[it->second].name, e.name));
    for (int c = 0; c < 3; ++c)
      if (!(e.color[c] >= 0.0f && e.color[c] <= 1.0f))
        throw Error(fmt::format("{}: label {} ('{}'): colour component {} is not in [0, 1]", what,
                                e.value, e.name, c + 1));
    if (!(e.opacity >= 0.0f && e.opacity <= 1.0f))
      throw Error(fmt::format("{}: label {} ('{}'): opacity {} is not in [0, 1]", what, e.value,
                              e.name, e.opacity));
  }
}

namespace labels_detail {

std::vector<LabelEntry> read_slicer_segments(const std::filesystem::path& file, int layer) {
  const std::string what = file.string();
  const std::string text = read_head(file, kMaxNrrdHeaderBytes, false);
  const size_t end = text.find("\n\n"), crlf_end = text.find("\r\n\r\n");
  const size_t header_end = std::min(end, crlf_end);
  if (header_end == std::string::npos && text.size() >= kMaxNrrdHeaderBytes)
    throw Error(fmt::format("{}: no end of the NRRD header in its first {} bytes", what,
                            kMaxNrrdHeaderBytes));
  const auto fields =
      nrrd_key_values(std::string_view(text).substr(
                          0, header_end == std::string::npos ? text.size() : header_end + 1),
                      what);
  const int layers = read_volume_header(file).frames;
  if (layer < 0 || layer >= layers)
    throw Error(fmt::format("{}: layer {} asked for; the segmentation has {} (0-{})", what, layer,
                            layers, layers - 1));
  return parse_slicer_segments(fields, layers, layer, what);
}

std::vector<LabelEntry> read_text_table(const std::filesystem::path& file, int layer) {
  const std::string what = file.string();
  if (layer != 0) throw Error(fmt::format("{}: only a 3D Slicer segmentation has layers", what));
  const std::string text = read_head(file, kMaxTableBytes, true);
  if (text.find('\0') != std::string::npos)
    throw Error(what + ": not a text colour table (it holds NUL bytes)");
  const std::string_view row = first_row(text);
  if (row.empty()) throw Error(what + ": no rows; an empty colour table");
  return row.find('"') != std::string_view::npos ? parse_itksnap_labels(text, what)
                                                 : parse_freesurfer_lut(text, what);
}

}  // namespace labels_detail

std::vector<LabelEntry> read_label_table(const std::filesystem::path& file, int layer) {
  const detail::FileProbe probe = detail::probe_file(file);
  // A table is known by its content: a NRRD is a segmentation, any other file text.
  const labels_detail::LabelTableFormat* format =
      detail::find_format(labels_detail::label_table_formats_table(), probe);
  std::vector<LabelEntry> entries = format ? format->read(file, layer)
                                    : labels_detail::looks_like_nrrd(probe.head)
                                        ? labels_detail::read_slicer_segments(file, layer)
                                        : labels_detail::read_text_table(file, layer);
  validate_label_entries(entries, file.string());
  return entries;
}

}  // namespace imx
