#include "io/tiff/ome_xml.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <type_traits>

#include <expat.h>
#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/xml_parser.hpp"

namespace imx::detail {

namespace {

// Sizes larger than this are not images but corrupt metadata (a grid's own limit comes later).
constexpr int64_t kMaxSize = int64_t{1} << 31;

// The local name of an element or attribute: "ome:Pixels" -> "Pixels".
std::string_view local(const char* name) {
  std::string_view s(name);
  const size_t colon = s.rfind(':');
  return colon == std::string_view::npos ? s : s.substr(colon + 1);
}

struct Parser {
  std::string what;
  OmePixels pixels;
  std::vector<std::string> stack;
  bool in_first_image = false, have_pixels = false;
  std::string fault;
  XML_Parser xml = nullptr;

  void fail(const std::string& why) {
    if (fault.empty()) fault = why;
    XML_StopParser(xml, XML_FALSE);
  }

  int64_t integer(std::string_view field, const char* text, int64_t smallest) const {
    errno = 0;
    char* end = nullptr;
    const long long v = std::strtoll(text, &end, 10);
    if (end == text || *end != '\0' || errno != 0 || v < smallest || v > kMaxSize)
      throw Error(fmt::format("{}: OME-XML attribute '{}' is '{}', not an integer from {} to 2^31",
                              what, field, text, smallest));
    return v;
  }

  double positive(std::string_view field, const char* text) const {
    char* end = nullptr;
    const double v = std::strtod(text, &end);
    if (end == text || *end != '\0' || !std::isfinite(v) || v <= 0)
      throw Error(fmt::format("{}: OME-XML attribute '{}' is '{}', not a positive number", what,
                              field, text));
    return v;
  }

  void start(const char* raw, const char** attrs) {
    const std::string_view name = local(raw);
    const std::string parent = stack.empty() ? "" : stack.back();
    stack.emplace_back(name);
    if (name == "Image" && parent == "OME") {
      in_first_image = ++pixels.images == 1;
      return;
    }
    if (!in_first_image) return;
    if (name == "Pixels" && parent == "Image" && !have_pixels) {
      have_pixels = true;
      read_pixels(attrs);
    } else if (name == "Channel" && parent == "Pixels") {
      for (const char** a = attrs; *a; a += 2)
        if (local(a[0]) == "SamplesPerPixel")
          pixels.samples_per_pixel = std::max<int>(
              pixels.samples_per_pixel, static_cast<int>(integer("SamplesPerPixel", a[1], 1)));
    } else if (name == "TiffData" && parent == "Pixels") {
      OmeTiffData d;
      for (const char** a = attrs; *a; a += 2) {
        const std::string_view key = local(a[0]);
        if (key == "IFD") d.ifd = integer("TiffData IFD", a[1], 0);
        if (key == "PlaneCount") d.plane_count = integer("TiffData PlaneCount", a[1], 0);
        if (key == "FirstZ") d.first_z = integer("TiffData FirstZ", a[1], 0);
        if (key == "FirstC") d.first_c = integer("TiffData FirstC", a[1], 0);
        if (key == "FirstT") d.first_t = integer("TiffData FirstT", a[1], 0);
      }
      pixels.tiff_data.push_back(d);
    } else if (name == "UUID" && parent == "TiffData") {
      for (const char** a = attrs; *a; a += 2)
        if (local(a[0]) == "FileName") pixels.tiff_data.back().file_name = a[1];
    }
  }

  void read_pixels(const char** attrs) {
    OmePixels& p = pixels;
    for (const char** a = attrs; *a; a += 2) {
      const std::string_view key = local(a[0]);
      const char* value = a[1];
      if (key == "SizeX") p.size_x = integer(key, value, 1);
      if (key == "SizeY") p.size_y = integer(key, value, 1);
      if (key == "SizeZ") p.size_z = integer(key, value, 1);
      if (key == "SizeC") p.size_c = integer(key, value, 1);
      if (key == "SizeT") p.size_t_ = integer(key, value, 1);
      if (key == "DimensionOrder") p.dimension_order = value;
      if (key == "Type") p.type = value;
      if (key == "BigEndian") p.big_endian = std::string_view(value) == "true";
      const char* axes[] = {"X", "Y", "Z"};
      for (int i = 0; i < 3; ++i) {
        if (key == fmt::format("PhysicalSize{}", axes[i]))
          p.physical_size[i] = positive(key, value);
        if (key == fmt::format("PhysicalSize{}Unit", axes[i])) p.physical_unit[i] = value;
      }
    }
    if (p.size_x == 0 || p.size_y == 0)
      throw Error(fmt::format("{}: OME-XML Pixels has no SizeX or SizeY", what));
    const std::string& o = p.dimension_order;
    if (o.size() != 5 || o.compare(0, 2, "XY") != 0 || o.find('Z') == std::string::npos ||
        o.find('C') == std::string::npos || o.find('T') == std::string::npos)
      throw Error(fmt::format(
          "{}: OME-XML attribute 'DimensionOrder' is '{}', not XY followed by Z, C and T", what,
          o));
  }
};

}  // namespace

int64_t OmePixels::plane_index(int64_t z, int64_t c, int64_t t) const {
  int64_t index = 0, stride = 1;
  for (size_t i = 2; i < 5; ++i) {
    const char axis = dimension_order[i];
    const int64_t at = axis == 'Z' ? z : axis == 'C' ? c : t;
    const int64_t size = axis == 'Z' ? size_z : axis == 'C' ? size_c : size_t_;
    index += at * stride;
    stride *= size;
  }
  return index;
}

bool is_ome_xml(std::string_view description) {
  const size_t at = description.find("<OME");
  if (at == std::string_view::npos) return false;
  const std::string_view before = description.substr(0, at);
  // Only an XML declaration, comments or blanks before the root.
  return before.find_first_not_of(" \t\r\n") == std::string_view::npos ||
         before.substr(before.find_first_not_of(" \t\r\n")).starts_with("<?xml");
}

OmePixels parse_ome_xml(std::string_view xml, const std::string& what) {
  if (xml.size() > kMaxOmeXmlBytes)
    throw Error(fmt::format("{}: {} bytes of OME-XML, more than the {} read", what, xml.size(),
                            kMaxOmeXmlBytes));
  Parser p;
  p.what = what;
  const XmlParser parser = make_xml_parser();
  if (!parser) throw Error(fmt::format("{}: cannot start the XML parser", what));
  p.xml = parser.get();
  XML_SetUserData(p.xml, &p);
  // No exception may cross expat's C frames: the handlers turn them into a stop.
  XML_SetElementHandler(
      p.xml,
      [](void* u, const char* name, const char** attrs) {
        auto* self = static_cast<Parser*>(u);
        try {
          self->start(name, attrs);
        } catch (const std::exception& e) {
          self->fail(e.what());
        }
      },
      [](void* u, const char*) {
        auto* self = static_cast<Parser*>(u);
        if (!self->stack.empty()) self->stack.pop_back();
      });
  // OME-XML needs no document type; entities are how XML bombs grow.
  XML_SetStartDoctypeDeclHandler(p.xml, [](void* u, const char*, const char*, const char*, int) {
    static_cast<Parser*>(u)->fail("the OME-XML declares a document type");
  });
  XML_SetEntityDeclHandler(
      p.xml, [](void* u, const char*, int, const char*, int, const char*, const char*, const char*,
                const char*) { static_cast<Parser*>(u)->fail("the OME-XML declares entities"); });
  if (XML_Parse(p.xml, xml.data(), static_cast<int>(xml.size()), XML_TRUE) == XML_STATUS_ERROR) {
    if (!p.fault.empty()) throw Error(p.fault.starts_with(what) ? p.fault : what + ": " + p.fault);
    throw Error(fmt::format("{}: the OME-XML is malformed: {} at line {}", what,
                            XML_ErrorString(XML_GetErrorCode(p.xml)),
                            XML_GetCurrentLineNumber(p.xml)));
  }
  if (!p.fault.empty()) throw Error(p.fault.starts_with(what) ? p.fault : what + ": " + p.fault);
  if (!p.have_pixels) throw Error(fmt::format("{}: the OME-XML has no Image with Pixels", what));
  return p.pixels;
}

}  // namespace imx::detail
