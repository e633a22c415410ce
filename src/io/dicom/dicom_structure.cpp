#include "io/dicom/dicom_structure.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "io/streams/input_file.hpp"

namespace imx::detail {

namespace {

constexpr int kMaxDepth = 32;  // nested sequences; real files use a handful
constexpr uint32_t kUndefined = 0xffffffffu;

// VRs whose length field is 4 bytes (after 2 reserved bytes) in explicit VR.
bool long_vr(const char* vr) {
  static const char* const kLong[] = {"OB", "OD", "OF", "OL", "OV", "OW", "SQ",
                                      "SV", "UC", "UN", "UR", "UT", "UV"};
  return std::any_of(std::begin(kLong), std::end(kLong),
                     [&](const char* v) { return std::memcmp(v, vr, 2) == 0; });
}

bool short_vr(const char* vr) {
  static const char* const kShort[] = {"AE", "AS", "AT", "CS", "DA", "DS", "DT",
                                       "FL", "FD", "IS", "LO", "LT", "PN", "SH",
                                       "SL", "SS", "ST", "TM", "UI", "UL", "US"};
  return std::any_of(std::begin(kShort), std::end(kShort),
                     [&](const char* v) { return std::memcmp(v, vr, 2) == 0; });
}

// Image tags GDCM reads through asserting templates: their VR (explicit files) must be this,
// and a US value must hold at least one whole value.
struct KnownTag {
  uint16_t group, element;
  const char* vr;
};
constexpr KnownTag kKnownTags[] = {
    {0x0018, 0x0050, "DS"}, {0x0018, 0x0088, "DS"}, {0x0018, 0x1164, "DS"}, {0x0018, 0x2010, "DS"},
    {0x0020, 0x0032, "DS"}, {0x0020, 0x0037, "DS"}, {0x0028, 0x0002, "US"}, {0x0028, 0x0004, "CS"},
    {0x0028, 0x0006, "US"}, {0x0028, 0x0008, "IS"}, {0x0028, 0x0010, "US"}, {0x0028, 0x0011, "US"},
    {0x0028, 0x0030, "DS"}, {0x0028, 0x0034, "IS"}, {0x0028, 0x0100, "US"}, {0x0028, 0x0101, "US"},
    {0x0028, 0x0102, "US"}, {0x0028, 0x0103, "US"}, {0x0028, 0x1050, "DS"}, {0x0028, 0x1051, "DS"},
    {0x0028, 0x1052, "DS"}, {0x0028, 0x1053, "DS"}, {0x0028, 0x1054, "LO"}};

const KnownTag* known_tag(uint16_t group, uint16_t element) {
  for (const KnownTag& k : kKnownTags)
    if (k.group == group && k.element == element) return &k;
  return nullptr;
}

class Walker {
 public:
  Walker(std::istream& in, uint64_t size) : in_(in), size_(size) {}

  std::string error;

  // Elements from `at` up to `end` (or a delimiter when `end` is nullopt) in one encoding.
  bool data_set(uint64_t at, std::optional<uint64_t> end, bool explicit_vr, bool big, int depth,
                uint64_t& stop) {
    if (depth > kMaxDepth) return fail(at, "sequences nested too deeply");
    uint32_t previous = 0;
    bool first = true;
    while (!end || at < *end) {
      uint8_t h[12];
      if (!read(at, h, 8)) return fail(at, "an element header runs past the end of the file");
      const uint16_t group = u16(h, big), element = u16(h + 2, big);
      // Ascending tags, as the standard requires: GDCM's partial reads stop at the first tag
      // past the one asked for, and would otherwise see other values than its full read.
      const uint32_t tag = uint32_t{group} << 16 | element;
      if (group != 0xfffe) {
        if (!first && tag <= previous)
          return fail(at, fmt::format("element ({:04X},{:04X}) is out of order", group, element));
        previous = tag;
        first = false;
      }
      if (const KnownTag* k = known_tag(group, element)) {
        if (explicit_vr && std::memcmp(h + 4, k->vr, 2) != 0)
          return fail(
              at, fmt::format("element ({:04X},{:04X}) has VR {}{}, expected {}", group, element,
                              static_cast<char>(h[4]), static_cast<char>(h[5]), k->vr));
        const uint32_t vl = explicit_vr ? u16(h + 6, big) : u32(h + 4, big);
        if (std::strcmp(k->vr, "US") == 0 && (vl < 2 || vl % 2 != 0))
          return fail(at, fmt::format("element ({:04X},{:04X}) has a US value of {} bytes", group,
                                      element, vl));
      }
      if (group == 0xfffe) {  // an item delimiter ends an undefined-length item
        if (element == 0xe00d && !end) {
          stop = at + 8;
          return true;
        }
        return fail(at, "an item tag where an element was expected");
      }
      uint64_t length;
      uint64_t value;
      bool sequence = false;
      if (explicit_vr) {
        const char vr[2] = {static_cast<char>(h[4]), static_cast<char>(h[5])};
        if (short_vr(vr)) {
          length = big ? (h[6] << 8 | h[7]) : (h[7] << 8 | h[6]);
          value = at + 8;
        } else if (long_vr(vr)) {
          if (!read(at, h, 12)) return fail(at, "an element header runs past the end");
          length = u32(h + 8, big);
          value = at + 12;
          sequence = std::memcmp(vr, "SQ", 2) == 0;
          if (std::memcmp(vr, "UN", 2) == 0 && length == kUndefined) {
            // An undefined-length UN is a sequence in implicit VR little endian (CP 246).
            uint64_t next;
            if (!items(value, std::nullopt, false, false, depth + 1, next)) return false;
            at = next;
            continue;
          }
        } else {
          return fail(at, fmt::format("element ({:04X},{:04X}) has no valid VR", group, element));
        }
      } else {
        length = u32(h + 4, big);
        value = at + 8;
      }
      const bool pixel_data = group == 0x7fe0 && element == 0x0010;
      if (length == kUndefined) {
        uint64_t next;
        if (pixel_data && !sequence) {
          if (!fragments(value, big, next)) return false;
        } else if (pixel_data) {
          return fail(at, "pixel data is a sequence");
        } else if (!items(value, std::nullopt, explicit_vr, big, depth + 1, next)) {
          return false;
        }
        at = next;
        continue;
      }
      if (length > remaining(value, end))
        return fail(at, fmt::format("element ({:04X},{:04X}) claims {} bytes, more than the file "
                                    "holds",
                                    group, element, length));
      if (pixel_data && sequence) return fail(at, "pixel data is a sequence");
      // A defined-length sequence (or, in implicit VR, a value that starts with an item).
      bool nested = sequence;
      if (!explicit_vr && length >= 8) {
        uint8_t first[4];
        nested =
            read(value, first, 4) && u16(first, big) == 0xfffe && u16(first + 2, big) == 0xe000;
      }
      if (nested && length > 0) {
        uint64_t next;
        if (!items(value, value + length, explicit_vr, big, depth + 1, next)) return false;
      }
      at = value + length;
    }
    if (end && at != *end) return fail(at, "elements overrun their item");
    stop = at;
    return true;
  }

 private:
  // Items of a sequence, up to `end` or the sequence delimiter.
  bool items(uint64_t at, std::optional<uint64_t> end, bool explicit_vr, bool big, int depth,
             uint64_t& stop) {
    if (depth > kMaxDepth) return fail(at, "sequences nested too deeply");
    while (!end || at < *end) {
      uint8_t h[8];
      if (!read(at, h, 8)) return fail(at, "a sequence runs past the end of the file");
      const uint16_t group = u16(h, big), element = u16(h + 2, big);
      const uint32_t length = u32(h + 4, big);
      if (group == 0xfffe && element == 0xe0dd && !end) {
        stop = at + 8;
        return true;
      }
      if (group != 0xfffe || element != 0xe000)
        return fail(at, "a sequence holds something other than items");
      const uint64_t value = at + 8;
      if (length == kUndefined) {
        uint64_t next;
        if (!data_set(value, std::nullopt, explicit_vr, big, depth + 1, next)) return false;
        at = next;
      } else {
        if (length > remaining(value, end)) return fail(at, "an item runs past its sequence");
        uint64_t next;
        if (!data_set(value, value + length, explicit_vr, big, depth + 1, next)) return false;
        at = value + length;
      }
    }
    if (end && at != *end) return fail(at, "items overrun their sequence");
    stop = at;
    return true;
  }

  // Encapsulated pixel data: items of defined length up to the sequence delimiter.
  bool fragments(uint64_t at, bool big, uint64_t& stop) {
    while (true) {
      uint8_t h[8];
      if (!read(at, h, 8)) return fail(at, "pixel data fragments run past the end of the file");
      const uint16_t group = u16(h, big), element = u16(h + 2, big);
      const uint32_t length = u32(h + 4, big);
      if (group == 0xfffe && element == 0xe0dd) {
        stop = at + 8;
        return true;
      }
      if (group != 0xfffe || element != 0xe000 || length == kUndefined ||
          length > remaining(at + 8, std::nullopt))
        return fail(at, "a malformed pixel data fragment");
      at += 8 + length;
    }
  }

  uint64_t remaining(uint64_t at, std::optional<uint64_t> end) const {
    const uint64_t limit = end ? std::min(*end, size_) : size_;
    return at <= limit ? limit - at : 0;
  }

  // Element headers come from a window of the file: one read serves the many small headers
  // between two large values.
  bool read(uint64_t at, uint8_t* out, size_t n) {
    if (at + n > size_) return false;
    if (at < window_at_ || at + n > window_at_ + window_.size()) {
      window_.resize(static_cast<size_t>(std::min<uint64_t>(kWindow, size_ - at)));
      in_.clear();
      in_.seekg(static_cast<std::streamoff>(at));
      in_.read(reinterpret_cast<char*>(window_.data()),
               static_cast<std::streamsize>(window_.size()));
      if (in_.gcount() != static_cast<std::streamsize>(window_.size())) {
        window_.clear();
        return false;
      }
      window_at_ = at;
    }
    std::memcpy(out, window_.data() + (at - window_at_), n);
    return true;
  }

  static constexpr uint64_t kWindow = 16384;
  std::vector<uint8_t> window_;
  uint64_t window_at_ = 0;

  bool fail(uint64_t at, const std::string& what) {
    error = fmt::format("{} (at byte {})", what, at);
    return false;
  }

  static uint16_t u16(const uint8_t* p, bool big) {
    return big ? static_cast<uint16_t>(p[0] << 8 | p[1]) : static_cast<uint16_t>(p[1] << 8 | p[0]);
  }
  static uint32_t u32(const uint8_t* p, bool big) {
    return big ? (uint32_t{p[0]} << 24 | uint32_t{p[1]} << 16 | uint32_t{p[2]} << 8 | p[3])
               : (uint32_t{p[3]} << 24 | uint32_t{p[2]} << 16 | uint32_t{p[1]} << 8 | p[0]);
  }

  std::istream& in_;
  uint64_t size_;
};

}  // namespace

std::string check_dicom_structure(const std::filesystem::path& file) {
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) return "cannot read its size";
  std::ifstream in = try_open_input_stream(file);
  if (!in) return "cannot open it";
  char head[132] = {};
  in.read(head, sizeof head);
  uint64_t at = 0;
  bool explicit_vr = true, big = false;
  if (in.gcount() == 132 && std::memcmp(head + 128, "DICM", 4) == 0) {
    // The meta group: explicit VR little endian; its transfer syntax says how the rest reads.
    at = 132;
    std::string ts;
    while (true) {
      uint8_t h[8];
      in.clear();
      in.seekg(static_cast<std::streamoff>(at));
      in.read(reinterpret_cast<char*>(h), 8);
      if (in.gcount() != 8 || (h[0] | h[1] << 8) != 0x0002) break;
      const char vr[2] = {static_cast<char>(h[4]), static_cast<char>(h[5])};
      uint64_t length, value;
      if (short_vr(vr)) {
        length = h[6] | h[7] << 8;
        value = at + 8;
      } else if (long_vr(vr) && std::memcmp(vr, "SQ", 2) != 0) {
        uint8_t l[4];
        in.read(reinterpret_cast<char*>(l), 4);
        if (in.gcount() != 4) return "the file meta information is cut short";
        length = uint32_t{l[3]} << 24 | uint32_t{l[2]} << 16 | uint32_t{l[1]} << 8 | l[0];
        value = at + 12;
      } else {
        return "a malformed file meta information element";
      }
      if (length == kUndefined || value + length > size)
        return "a file meta information element runs past the end of the file";
      if ((h[2] | h[3] << 8) == 0x0010 && length < 256) {
        std::string s(static_cast<size_t>(length), '\0');
        in.clear();
        in.seekg(static_cast<std::streamoff>(value));
        in.read(s.data(), static_cast<std::streamsize>(length));
        while (!s.empty() && (s.back() == '\0' || s.back() == ' ')) s.pop_back();
        ts = s;
      }
      at = value + length;
    }
    if (ts == "1.2.840.10008.1.2") explicit_vr = false;
    if (ts == "1.2.840.10008.1.2.2") big = true;
    if (ts == "1.2.840.10008.1.2.1.99") return "deflated transfer syntax (not supported)";
  } else {
    // A bare data set: implicit unless the first element carries a VR.
    in.clear();
    in.seekg(0);
    uint8_t h[6] = {};
    in.read(reinterpret_cast<char*>(h), 6);
    const char vr[2] = {static_cast<char>(h[4]), static_cast<char>(h[5])};
    explicit_vr = short_vr(vr) || long_vr(vr);
  }
  Walker walker(in, size);
  uint64_t stop = 0;
  if (!walker.data_set(at, size, explicit_vr, big, 0, stop)) return walker.error;
  return "";
}

}  // namespace imx::detail
