#include "io/volume/nrrd_data.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <memory>
#include <span>
#include <system_error>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/bzip2.hpp"
#include "io/streams/gzip.hpp"
#include "io/streams/inflate_charge.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"
#include "io/voxels/mapped_voxels.hpp"
#include "io/voxels/text_voxels.hpp"

// How the data is found, following teem's reader (format.html and formatNRRD.c/read.c): in each
// data file, first 'line skip' lines are skipped, on the file's own bytes whatever the
// encoding; then 'byte skip' bytes: of the file for raw, ascii and hex, but of the decompressed
// stream for gzip and bzip2 (teem skips those inside the stream). 'byte skip: -1' (raw only)
// puts the data at the end of the file. Several data files each hold an equal share of the
// elements, in order, and each gets the skips.
//
// Where teem reads whatever bytes lie there, this reader refuses data that does not fit, since
// a wrong size almost always means the header is wrong and the voxels would be garbage: raw
// data must fill its file exactly unless a byte skip says where it starts (a .nii named as the
// data file without 'byte skip: 352' would read its header as voxels); detached compressed
// data likewise must end where the voxels do; text data must hold exactly the header's count
// of values. Attached compressed data keeps the tolerance of up to 1 MiB of decompressed bytes
// after the voxels that GzipStream::finish allows (nothing but the stream follows the header
// there, and some writers pad).

namespace imx::detail {

namespace {

// Scratch for reading interleaved frames: rows are read in pieces of at most this much.
constexpr size_t kScratchBytes = size_t{1} << 20;
// Decompressed bytes after the voxels that are counted for the message before giving up.
constexpr size_t kSurplusCount = size_t{1} << 20;

const char* encoding_name(NrrdEncoding e) {
  switch (e) {
    case NrrdEncoding::raw:
      return "raw";
    case NrrdEncoding::gzip:
      return "gzip";
    case NrrdEncoding::bzip2:
      return "bzip2";
    case NrrdEncoding::ascii:
      return "ascii";
    case NrrdEncoding::hex:
      return "hex";
  }
  return "raw";
}

// One data file (or the header holding attached data), located and checked by its size.
struct DataFile {
  std::filesystem::path path;
  std::string what;       // names it in messages
  uint64_t start = 0;     // where reading begins: after the skips on the file's own bytes
  uint64_t size = 0;      // the file's size in bytes
  uint64_t elements = 0;  // its share of the elements
  uint64_t bytes = 0;     // ... and their bytes once decoded
  std::string share;      // "4x3x2 int16", or with "(file 2 of 3)"
};

// The data's bytes (after a header, else in a data file) as something to read from.
std::ifstream open_data(const DataFile& f) {
  std::ifstream in = open_input_stream(f.path, f.what);
  return in;
}

// Locates the data of file `index`: resolves its name, skips its lines and (uncompressed) bytes,
// and checks its size against its share of the elements, so that a short or mismatched file is
// refused before any voxel memory is allocated.
DataFile survey(const NrrdData& d, size_t index, uint64_t elements) {
  DataFile f;
  f.elements = elements;
  f.bytes = elements * raw_type_size(d.type);
  f.share = fmt::format("{} {}", d.shape, raw_type_name(d.type));
  if (d.files.size() > 1) f.share += fmt::format(", file {} of {}", index + 1, d.files.size());
  const std::string header_what = d.header.string();
  uint64_t start = 0;
  if (d.files.empty()) {
    f.path = d.header;
    f.what = header_what;
    start = d.attached_offset;
  } else {
    f.path = resolve_data_file(d.header, d.files[index], "field 'data file'");
    f.what = fmt::format("{} (data file of {})", f.path.string(), header_what);
  }
  std::error_code ec;
  f.size = std::filesystem::file_size(f.path, ec);
  if (ec)
    throw Error(fmt::format("{}: cannot read the size of the data: {}", f.what, ec.message()));

  std::ifstream in = open_data(f);
  in.seekg(static_cast<std::streamoff>(start));
  std::streambuf& buf = *in.rdbuf();
  for (long long i = 0; i < d.line_skip; ++i) {
    int c;
    while ((c = buf.sbumpc()) != '\n')
      if (c == std::char_traits<char>::eof())
        throw Error(fmt::format("{}: field 'line skip' {} goes past the end of the data", f.what,
                                d.line_skip));
  }
  start = static_cast<uint64_t>(in.tellg());
  const uint64_t skip = d.byte_skip && *d.byte_skip > 0 ? static_cast<uint64_t>(*d.byte_skip) : 0;
  auto after = [&](uint64_t at) { return f.size > at ? f.size - at : 0; };

  switch (d.encoding) {
    case NrrdEncoding::raw: {
      uint64_t offset = start + skip;
      if (d.byte_skip == -1) offset = std::max(start, f.size >= f.bytes ? f.size - f.bytes : 0);
      const uint64_t found = after(offset);
      if (found < f.bytes)
        throw Error(fmt::format("{}: expected {} bytes of voxel data ({}), found {}", f.what,
                                f.bytes, f.share, found));
      if (found > f.bytes && !d.byte_skip)
        throw Error(
            fmt::format("{}: the {} has {} bytes more than the {} bytes of voxels ({}); "
                        "give 'byte skip' (the bytes before the voxels, or -1 when the "
                        "voxels end the file)",
                        f.what, d.files.empty() ? "data after the header" : "data file",
                        found - f.bytes, f.bytes, f.share));
      f.start = offset;
      break;
    }
    case NrrdEncoding::gzip:
      check_inflatable(f.bytes + skip, after(start), f.what);
      f.start = start;
      break;
    case NrrdEncoding::bzip2:
      check_bzip2_inflatable(f.bytes + skip, after(start), f.what);
      f.start = start;
      break;
    case NrrdEncoding::ascii:
    case NrrdEncoding::hex: {
      if (skip > after(start))
        throw Error(
            fmt::format("{}: field 'byte skip' {} goes past the end of the data", f.what, skip));
      // The least text that can hold the data, checked before anything is allocated: a digit
      // and a separator per value (the last needs none), two digits per hex byte.
      const uint64_t found = after(start + skip);
      const bool ascii = d.encoding == NrrdEncoding::ascii;
      const uint64_t least = ascii ? 2 * f.elements - 1 : 2 * f.bytes;
      if (found < least)
        throw Error(
            fmt::format("{}: {} bytes of {} data cannot hold the {} {} ({}): at least "
                        "{} bytes are needed",
                        f.what, found, encoding_name(d.encoding), ascii ? f.elements : f.bytes,
                        ascii ? "values" : "bytes", f.share, least));
      f.start = start + skip;
      break;
    }
  }
  return f;
}

// The decoded bytes of one data file, read in increasing order of offset.
class Piece {
 public:
  virtual ~Piece() = default;
  // Copies decoded bytes [offset, offset + out.size()) of the file's share into `out`; offset
  // is at or after the end of the previous read.
  virtual void read(uint64_t offset, std::span<uint8_t> out) = 0;
  // Checks the rest of the file: decodes sequential data to its end.
  virtual void finish() = 0;
};

class RawPiece final : public Piece {
 public:
  explicit RawPiece(const DataFile& f) : file_(f), in_(open_data(f)) {}

  void read(uint64_t offset, std::span<uint8_t> out) override {
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(file_.start + offset));
    in_.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(out.size()));
    // The size was checked; a file that shrinks meanwhile still gets a message.
    if (static_cast<size_t>(in_.gcount()) != out.size())
      throw Error(fmt::format("{}: expected {} bytes of voxel data at byte {}, found {}",
                              file_.what, out.size(), file_.start + offset, in_.gcount()));
  }
  void finish() override {}

 private:
  const DataFile& file_;
  std::ifstream in_;
};

// gzip or bzip2 data (Stream: GzipStream or Bzip2Stream), decompressed from the start.
template <class Stream>
class CompressedPiece final : public Piece {
 public:
  CompressedPiece(const DataFile& f, const NrrdData& d, const char* name)
      : file_(f), name_(name), in_(open_data(f)), stream_(in_, f.what) {
    in_.seekg(static_cast<std::streamoff>(f.start));
    skip_ = d.byte_skip ? static_cast<uint64_t>(*d.byte_skip) : 0;
    strict_ = !d.files.empty() && !d.byte_skip;
    if (stream_.skip(static_cast<size_t>(skip_)) < skip_) throw short_data(0);
  }

  void read(uint64_t offset, std::span<uint8_t> out) override {
    advance(offset);
    const size_t got = stream_.read(out);
    at_ += got;
    if (got < out.size()) throw short_data(at_);
  }

  void finish() override {
    advance(file_.bytes);
    if (strict_) {
      const size_t extra = stream_.skip(kSurplusCount + 1);
      if (extra > 0)
        throw Error(fmt::format(
            "{}: the decompressed data file has {} bytes more than the {} bytes of voxels ({}); "
            "give 'byte skip' (the decompressed bytes before the voxels)",
            file_.what,
            extra > kSurplusCount ? fmt::format("over {}", kSurplusCount)
                                  : fmt::format("{}", extra),
            file_.bytes, file_.share));
    }
    stream_.finish(static_cast<size_t>(file_.bytes));
  }

 private:
  void advance(uint64_t offset) {
    if (offset <= at_) return;
    at_ += stream_.skip(static_cast<size_t>(offset - at_));
    if (at_ < offset) throw short_data(at_);
  }
  Error short_data(uint64_t found) const {
    return Error(
        fmt::format("{}: expected {} bytes of voxel data ({}) after {} decompression{}, "
                    "found {} (truncated file?)",
                    file_.what, file_.bytes, file_.share, name_,
                    skip_ > 0 ? fmt::format(" and a byte skip of {}", skip_) : "", found));
  }

  const DataFile& file_;
  const char* name_;
  std::ifstream in_;
  Stream stream_;
  uint64_t skip_ = 0;
  bool strict_ = false;
  uint64_t at_ = 0;  // decompressed bytes passed, counted from the voxels' start
};

class AsciiPiece final : public Piece {
 public:
  AsciiPiece(const DataFile& f, RawType type)
      : file_(f),
        size_(raw_type_size(type)),
        in_(open_data(f)),
        values_(seek(in_, f), type, f.what) {}

  void read(uint64_t offset, std::span<uint8_t> out) override {
    const uint64_t first = offset / size_;
    if (first > values_.values_read()) values_.skip(first - values_.values_read(), file_.elements);
    values_.read(out, file_.elements);
  }
  void finish() override {
    if (file_.elements > values_.values_read())
      values_.skip(file_.elements - values_.values_read(), file_.elements);
    values_.expect_end(file_.elements);
  }

 private:
  static std::istream& seek(std::ifstream& in, const DataFile& f) {
    in.seekg(static_cast<std::streamoff>(f.start));
    return in;
  }

  const DataFile& file_;
  size_t size_;
  std::ifstream in_;
  AsciiValues values_;
};

class HexPiece final : public Piece {
 public:
  explicit HexPiece(const DataFile& f)
      : file_(f), in_(open_data(f)), bytes_(seek(in_, f), f.what) {}

  void read(uint64_t offset, std::span<uint8_t> out) override {
    if (offset > at_) bytes_.skip(offset - at_, file_.bytes);
    bytes_.read(out, file_.bytes);
    at_ = offset + out.size();
  }
  void finish() override {
    if (file_.bytes > at_) bytes_.skip(file_.bytes - at_, file_.bytes);
    at_ = file_.bytes;
    bytes_.expect_end(file_.bytes);
  }

 private:
  static std::istream& seek(std::ifstream& in, const DataFile& f) {
    in.seekg(static_cast<std::streamoff>(f.start));
    return in;
  }

  const DataFile& file_;
  std::ifstream in_;
  HexBytes bytes_;
  uint64_t at_ = 0;
};

// The decoded bytes of all the data files one after another, opened as reading reaches them.
class DataSource {
 public:
  DataSource(const NrrdData& d, const std::vector<DataFile>& files)
      : data_(d), files_(files), piece_bytes_(files.front().bytes) {}

  void read(uint64_t offset, std::span<uint8_t> out) {
    while (!out.empty()) {
      const size_t index = static_cast<size_t>(offset / piece_bytes_);
      const uint64_t local = offset % piece_bytes_;
      if (!piece_ || index != current_) {
        if (piece_) piece_->finish();
        piece_ = open(files_.at(index));
        current_ = index;
      }
      const size_t n = static_cast<size_t>(std::min<uint64_t>(out.size(), piece_bytes_ - local));
      piece_->read(local, out.first(n));
      offset += n;
      out = out.subspan(n);
    }
  }
  void finish() {
    if (piece_) piece_->finish();
    piece_.reset();
  }

 private:
  std::unique_ptr<Piece> open(const DataFile& f) const {
    switch (data_.encoding) {
      case NrrdEncoding::raw:
        return std::make_unique<RawPiece>(f);
      case NrrdEncoding::gzip:
        return std::make_unique<CompressedPiece<GzipStream>>(f, data_, "gzip");
      case NrrdEncoding::bzip2:
        return std::make_unique<CompressedPiece<Bzip2Stream>>(f, data_, "bzip2");
      case NrrdEncoding::ascii:
        return std::make_unique<AsciiPiece>(f, data_.type);
      case NrrdEncoding::hex:
        return std::make_unique<HexPiece>(f);
    }
    return nullptr;
  }

  const NrrdData& data_;
  const std::vector<DataFile>& files_;
  uint64_t piece_bytes_;
  std::unique_ptr<Piece> piece_;
  size_t current_ = 0;
};

}  // namespace

VoxelStorage read_nrrd_voxels(const NrrdData& data, const NrrdGrid& grid, int frame,
                              const VoxelBox& box) {
  const size_t file_count = std::max<size_t>(data.files.size(), 1);
  std::vector<DataFile> files;
  files.reserve(file_count);
  for (size_t i = 0; i < file_count; ++i)
    files.push_back(survey(data, i, data.elements / file_count));
  // Before the box's own limits: compressed data has no bricks to fall back on, so one frame of
  // it must be one a whole read may take.
  if (data.encoding == NrrdEncoding::gzip || data.encoding == NrrdEncoding::bzip2) {
    const uint64_t frame_voxels = VoxelBox::whole(grid.dims).count();
    refuse_compressed_claim(
        frame_voxels * raw_type_size(data.type), frame_voxels > kMaxVoxels, data.header.string(),
        fmt::format("{} voxel data{}", data.encoding == NrrdEncoding::gzip ? "gzip" : "bzip2",
                    grid.frames > 1 ? " of one frame" : ""));
  }
  require_loadable_box(box, data.header.string());

  const size_t size = raw_type_size(data.type);
  const bool swap = data.big_endian && data.encoding != NrrdEncoding::ascii;
  const uint64_t sx = grid.stride[0];
  const uint64_t base = static_cast<uint64_t>(frame) * grid.frame_stride;
  const size_t width = static_cast<size_t>(box.hi.x - box.lo.x);
  // A whole frame of native, uncompressed voxels lying in one run of one file: viewed in place.
  const glm::ivec3& n = grid.dims;
  if (data.encoding == NrrdEncoding::raw && file_count == 1 && !swap && sx == 1 &&
      box == VoxelBox::whole(n) && grid.stride[1] == static_cast<uint64_t>(n.x) &&
      grid.stride[2] == static_cast<uint64_t>(n.x) * n.y)
    if (auto mapped =
            map_voxels(files[0].path, files[0].start + base * size, data.type, box.count()))
      return std::move(*mapped);
  DataSource source(data, files);
  VoxelStorage voxels =
      load_voxels(data.type, box.count(), swap, data.header.string(), [&](std::span<uint8_t> out) {
        size_t at = 0;
        // Contiguous rows: runs of rows that follow each other in the data are read at once.
        uint64_t run_start = 0;
        size_t run_length = 0;
        auto flush = [&] {
          if (run_length == 0) return;
          source.read(run_start, out.subspan(at, run_length));
          at += run_length;
          run_length = 0;
        };
        // Interleaved rows (frames fastest): read a stretch and keep one element in sx.
        std::vector<uint8_t> scratch;
        const size_t per_piece =
            sx == 1
                ? 0
                : static_cast<size_t>(std::max<uint64_t>(1, (kScratchBytes / size - 1) / sx + 1));
        for (int k = box.lo.z; k < box.hi.z; ++k)
          for (int j = box.lo.y; j < box.hi.y; ++j) {
            const uint64_t first = base + static_cast<uint64_t>(k) * grid.stride[2] +
                                   static_cast<uint64_t>(j) * grid.stride[1] +
                                   static_cast<uint64_t>(box.lo.x) * sx;
            if (sx == 1) {
              if (run_length > 0 && first * size == run_start + run_length) {
                run_length += width * size;
                continue;
              }
              flush();
              run_start = first * size;
              run_length = width * size;
              continue;
            }
            for (size_t i0 = 0; i0 < width; i0 += per_piece) {
              const size_t m = std::min(per_piece, width - i0);
              scratch.resize(((m - 1) * sx + 1) * size);
              source.read((first + i0 * sx) * size, scratch);
              for (size_t q = 0; q < m; ++q, at += size)
                std::memcpy(out.data() + at, scratch.data() + q * sx * size, size);
            }
          }
        flush();
      });
  source.finish();
  return voxels;
}

}  // namespace imx::detail
