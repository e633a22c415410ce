// The zip format as PKWARE's APPNOTE lays it out: the end-of-central-directory record (found
// from the end, past the archive's comment), its zip64 locator and record, then one central
// record per member, whose zip64 extra field holds the sizes and offset that overflow 32 bits.
#include "io/streams/zip_archive.hpp"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "intermix/limits.hpp"
#include "io/streams/gzip.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/regular_file.hpp"

namespace imx::detail {

namespace {

constexpr uint32_t kEndSignature = 0x06054b50;
constexpr uint32_t kZip64LocatorSignature = 0x07064b50;
constexpr uint32_t kZip64EndSignature = 0x06064b50;
constexpr uint32_t kCentralSignature = 0x02014b50;
constexpr uint32_t kLocalSignature = 0x04034b50;
constexpr size_t kEndBytes = 22, kZip64LocatorBytes = 20, kZip64EndBytes = 56;
constexpr size_t kCentralBytes = 46, kLocalBytes = 30;
constexpr size_t kMaxCommentBytes = 65535;
constexpr uint16_t kEncryptedFlag = 1;
constexpr uint16_t kMethodStored = 0, kMethodDeflate = 8;
constexpr size_t kInputBytes = size_t{256} << 10;

template <class T>
T field(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);  // zip is little-endian, as is the host (trx_reader asserts it)
  return v;
}

}  // namespace

struct ZipArchive::Inflater {
  z_stream z{};
  std::vector<uint8_t> input = std::vector<uint8_t>(kInputBytes);
  bool ended = false;  // the deflate stream's end was reached
  Inflater() {
    if (inflateInit2(&z, -MAX_WBITS) != Z_OK) throw std::bad_alloc();
  }
  ~Inflater() { inflateEnd(&z); }
  Inflater(const Inflater&) = delete;
  Inflater& operator=(const Inflater&) = delete;
};

ZipArchive::ZipArchive(const std::filesystem::path& file, std::string what)
    : what_(std::move(what)) {
  const InputFd fd = open_input(file, what_);
  archive_bytes_ = fd.size();
  in_.open(path_of_open(fd, file), std::ios::binary);
  if (!in_) throw FileError(fmt::format("{}: cannot open file", what_), errno);
  if (archive_bytes_ < kEndBytes) fail("not a zip archive (too short for its directory)");

  // The end record: the last signature whose comment reaches exactly to the end of the file.
  const size_t tail_bytes =
      static_cast<size_t>(std::min<uint64_t>(archive_bytes_, kEndBytes + kMaxCommentBytes));
  std::vector<uint8_t> tail(tail_bytes);
  const uint64_t tail_start = archive_bytes_ - tail_bytes;
  read_at(tail_start, tail.data(), tail.size(), "its end");
  size_t end = SIZE_MAX;
  for (size_t i = tail_bytes - kEndBytes + 1; i-- > 0;)
    if (field<uint32_t>(&tail[i]) == kEndSignature &&
        i + kEndBytes + field<uint16_t>(&tail[i + 20]) == tail_bytes) {
      end = i;
      break;
    }
  if (end == SIZE_MAX) fail("not a zip archive (no end of central directory record)");
  const uint8_t* e = &tail[end];
  uint64_t disk = field<uint16_t>(e + 4), directory_disk = field<uint16_t>(e + 6);
  uint64_t count = field<uint16_t>(e + 10), directory_bytes = field<uint32_t>(e + 12);
  uint64_t directory_offset = field<uint32_t>(e + 16);
  const uint64_t end_offset = tail_start + end;
  if (count == 0xffff || directory_bytes == 0xffffffff || directory_offset == 0xffffffff) {
    uint8_t locator[kZip64LocatorBytes], end64[kZip64EndBytes];
    if (end_offset < kZip64LocatorBytes) fail("corrupt zip64 directory (no locator)");
    read_at(end_offset - kZip64LocatorBytes, locator, sizeof locator, "its zip64 locator");
    if (field<uint32_t>(locator) != kZip64LocatorSignature)
      fail("corrupt zip64 directory (no locator before the end record)");
    const uint64_t end64_offset = field<uint64_t>(locator + 8);
    if (archive_bytes_ < kZip64EndBytes || end64_offset > archive_bytes_ - kZip64EndBytes)
      fail(fmt::format("corrupt zip64 directory (its end record at byte {})", end64_offset));
    read_at(end64_offset, end64, sizeof end64, "its zip64 end record");
    if (field<uint32_t>(end64) != kZip64EndSignature)
      fail("corrupt zip64 directory (no zip64 end record where its locator says)");
    disk = field<uint32_t>(end64 + 16);
    directory_disk = field<uint32_t>(end64 + 20);
    count = field<uint64_t>(end64 + 32);
    directory_bytes = field<uint64_t>(end64 + 40);
    directory_offset = field<uint64_t>(end64 + 48);
  }
  if (disk != 0 || directory_disk != 0) fail("a zip archive split over several disks");
  if (directory_offset > archive_bytes_ || directory_bytes > archive_bytes_ - directory_offset)
    fail(fmt::format("corrupt zip directory ({} bytes at byte {}, in a {}-byte file)",
                     directory_bytes, directory_offset, archive_bytes_));
  if (count > directory_bytes / kCentralBytes)
    fail(fmt::format("the zip directory claims {} members, more than its {} bytes can hold", count,
                     directory_bytes));
  check_memory(directory_bytes * 2, what_);
  std::vector<uint8_t> dir(static_cast<size_t>(directory_bytes));
  read_at(directory_offset, dir.data(), dir.size(), "its central directory");

  members_.reserve(static_cast<size_t>(count));
  size_t at = 0;
  for (uint64_t i = 0; i < count; ++i) {
    if (dir.size() - at < kCentralBytes || field<uint32_t>(&dir[at]) != kCentralSignature)
      fail(fmt::format("corrupt zip directory (record {} of {})", i + 1, count));
    const uint8_t* r = &dir[at];
    const size_t name_bytes = field<uint16_t>(r + 28), extra_bytes = field<uint16_t>(r + 30);
    const size_t comment_bytes = field<uint16_t>(r + 32);
    if (dir.size() - at - kCentralBytes < name_bytes + extra_bytes + comment_bytes)
      fail(fmt::format("corrupt zip directory (record {} of {} runs past it)", i + 1, count));
    ZipMember m;
    m.flags = field<uint16_t>(r + 8);
    m.method = field<uint16_t>(r + 10);
    m.crc = field<uint32_t>(r + 16);
    m.compressed_size = field<uint32_t>(r + 20);
    m.size = field<uint32_t>(r + 24);
    m.header_offset = field<uint32_t>(r + 42);
    m.name.assign(reinterpret_cast<const char*>(r + kCentralBytes), name_bytes);
    m.directory = !m.name.empty() && m.name.back() == '/';
    // The zip64 extra field: 8-byte values for exactly the fields that hold 0xffffffff.
    const uint8_t* x = r + kCentralBytes + name_bytes;
    for (size_t k = 0; k + 4 <= extra_bytes;) {
      const uint16_t id = field<uint16_t>(x + k), bytes = field<uint16_t>(x + k + 2);
      if (k + 4 + bytes > extra_bytes) break;
      if (id == 0x0001) {
        size_t v = k + 4;
        for (uint64_t* value : {&m.size, &m.compressed_size, &m.header_offset}) {
          if (*value != 0xffffffff) continue;
          if (v + 8 > k + 4 + bytes)
            fail(fmt::format("member '{}': its zip64 extra field is too short", m.name));
          *value = field<uint64_t>(x + v);
          v += 8;
        }
      }
      k += 4 + bytes;
    }
    members_.push_back(std::move(m));
    at += kCentralBytes + name_bytes + extra_bytes + comment_bytes;
  }
}

ZipArchive::~ZipArchive() = default;

void ZipArchive::fail(const std::string& message) const {
  throw Error(fmt::format("{}: {}", what_, message));
}

void ZipArchive::read_at(uint64_t offset, void* dst, size_t n, const char* field_name) {
  in_.clear();
  in_.seekg(static_cast<std::streamoff>(offset));
  in_.read(static_cast<char*>(dst), static_cast<std::streamsize>(n));
  if (static_cast<size_t>(in_.gcount()) != n)
    fail(fmt::format("cannot read {} ({} bytes at byte {}): truncated archive?", field_name, n,
                     offset));
}

void ZipArchive::open(size_t index) {
  const ZipMember& m = members_.at(index);
  current_ = nullptr;
  inflater_.reset();
  if ((m.flags & kEncryptedFlag) != 0)
    fail(fmt::format("member '{}' is encrypted, which is not supported", m.name));
  if (m.method != kMethodStored && m.method != kMethodDeflate)
    fail(
        fmt::format("member '{}' uses zip compression method {}; only stored (0) and deflate (8) "
                    "are supported",
                    m.name, m.method));
  if (m.method == kMethodStored && m.compressed_size != m.size)
    fail(fmt::format("member '{}' is stored, but its size {} differs from its stored size {}",
                     m.name, m.size, m.compressed_size));
  if (m.method == kMethodDeflate)
    check_inflatable(static_cast<size_t>(std::min<uint64_t>(m.size, SIZE_MAX)),
                     static_cast<size_t>(m.compressed_size),
                     fmt::format("{}: member '{}'", what_, m.name));
  if (archive_bytes_ < kLocalBytes || m.header_offset > archive_bytes_ - kLocalBytes)
    fail(fmt::format("member '{}': its local header at byte {} lies past the end", m.name,
                     m.header_offset));
  uint8_t local[kLocalBytes];
  read_at(m.header_offset, local, sizeof local, "a local header");
  if (field<uint32_t>(local) != kLocalSignature)
    fail(fmt::format("member '{}': no local header at byte {}", m.name, m.header_offset));
  const uint64_t data =
      m.header_offset + kLocalBytes + field<uint16_t>(local + 26) + field<uint16_t>(local + 28);
  if (data > archive_bytes_ || m.compressed_size > archive_bytes_ - data)
    fail(
        fmt::format("member '{}': its {} compressed bytes at byte {} run past the end of the "
                    "{}-byte archive (truncated?)",
                    m.name, m.compressed_size, data, archive_bytes_));
  in_.clear();
  in_.seekg(static_cast<std::streamoff>(data));
  current_ = &m;
  compressed_left_ = m.compressed_size;
  read_ = 0;
  crc_ = static_cast<uint32_t>(crc32(0, nullptr, 0));
  if (m.method == kMethodDeflate) inflater_ = std::make_unique<Inflater>();
}

size_t ZipArchive::fetch() {
  Inflater& f = *inflater_;
  const size_t n = static_cast<size_t>(std::min<uint64_t>(compressed_left_, f.input.size()));
  in_.read(reinterpret_cast<char*>(f.input.data()), static_cast<std::streamsize>(n));
  if (static_cast<size_t>(in_.gcount()) != n)
    fail(fmt::format("member '{}': cannot read its compressed data (truncated archive?)",
                     current_->name));
  compressed_left_ -= n;
  f.z.next_in = f.input.data();
  f.z.avail_in = static_cast<uInt>(n);
  return n;
}

void ZipArchive::read(std::span<uint8_t> piece) {
  if (current_ == nullptr) fail("reading a zip member that is not open");
  const ZipMember& m = *current_;
  if (piece.size() > m.size - read_)
    fail(fmt::format("member '{}': reading past its {} bytes", m.name, m.size));
  size_t done = 0;
  if (!inflater_) {
    in_.read(reinterpret_cast<char*>(piece.data()), static_cast<std::streamsize>(piece.size()));
    done = static_cast<size_t>(in_.gcount());
    if (done != piece.size())
      fail(fmt::format("member '{}' ends after {} of its {} bytes (truncated archive?)", m.name,
                       read_ + done, m.size));
    compressed_left_ -= done;
  } else {
    Inflater& f = *inflater_;
    while (done < piece.size()) {
      if (f.ended)
        fail(fmt::format("member '{}' inflates to {} bytes, not the {} its zip directory says",
                         m.name, read_ + done, m.size));
      const bool no_input = f.z.avail_in == 0 && fetch() == 0;
      const size_t room = std::min<size_t>(piece.size() - done, 1u << 30);
      f.z.next_out = piece.data() + done;
      f.z.avail_out = static_cast<uInt>(room);
      const int status = inflate(&f.z, Z_NO_FLUSH);
      if (status != Z_OK && status != Z_STREAM_END && status != Z_BUF_ERROR)
        fail(fmt::format("member '{}': corrupt deflate data", m.name));
      f.ended = status == Z_STREAM_END;
      done += room - f.z.avail_out;
      if (no_input && !f.ended && f.z.avail_out == room)  // no input left, and no progress
        fail(
            fmt::format("member '{}': its compressed data ends after {} of its {} bytes "
                        "(truncated archive?)",
                        m.name, read_ + done, m.size));
    }
  }
  crc_ = static_cast<uint32_t>(crc32_z(crc_, piece.data(), piece.size()));
  read_ += done;
}

void ZipArchive::finish() {
  if (current_ == nullptr) fail("finishing a zip member that is not open");
  const ZipMember& m = *current_;
  current_ = nullptr;
  if (read_ != m.size) fail(fmt::format("member '{}': read only in part", m.name));
  if (inflater_) {
    // Its deflate data must end here: one byte more is refused without inflating the rest.
    Inflater& f = *inflater_;
    uint8_t extra = 0;
    while (!f.ended) {
      const bool no_input = f.z.avail_in == 0 && fetch() == 0;
      f.z.next_out = &extra;
      f.z.avail_out = 1;
      const int status = inflate(&f.z, Z_NO_FLUSH);
      if (status != Z_OK && status != Z_STREAM_END && status != Z_BUF_ERROR)
        fail(fmt::format("member '{}': corrupt deflate data", m.name));
      if (f.z.avail_out == 0)
        fail(fmt::format("member '{}' inflates to more than the {} bytes its zip directory says",
                         m.name, m.size));
      f.ended = status == Z_STREAM_END;
      if (no_input && !f.ended)
        fail(fmt::format("member '{}': its compressed data is cut short", m.name));
    }
    inflater_.reset();
  }
  if (crc_ != m.crc)
    fail(
        fmt::format("member '{}': CRC mismatch ({:08x}, its directory says {:08x}): corrupt "
                    "data",
                    m.name, crc_, m.crc));
}

}  // namespace imx::detail
