#include "io/overlay/cifti_xml.hpp"

#include <cctype>
#include <charconv>
#include <climits>
#include <exception>
#include <memory>
#include <optional>
#include <type_traits>

#include <expat.h>
#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/xml_parser.hpp"

namespace imx::detail {
namespace {

// Text kept for a label's or a map's name: longer is cut (a name is for display only).
constexpr size_t kMaxNameBytes = 4096;
// Brain models in a file: CIFTI names some 30 structures, each a surface or voxels.
constexpr size_t kMaxBrainModels = 1024;

const char* attribute(const char** attrs, const char* name) {
  for (size_t i = 0; attrs[i]; i += 2)
    if (std::string_view(attrs[i]) == name) return attrs[i + 1];
  return nullptr;
}

struct Parser {
  XML_Parser xml = nullptr;
  std::string fault;
  std::vector<std::string> stack;  // open elements
  CiftiXml out;
  std::string text;  // the open MapName's, Label's or VertexIndices' text
  bool keep_text = false;
  OverlayLabel label;          // the open Label
  int64_t vertex_indices = 0;  // in the whole file, against kMaxCiftiBrainordinates

  void fail(std::string message) {
    if (fault.empty()) fault = std::move(message);
    XML_StopParser(xml, XML_FALSE);
  }

  const std::string& parent() const {
    static const std::string none;
    return stack.empty() ? none : stack.back();
  }

  void require_parent(const std::string& name, const char* want) {
    if (parent() != want)
      throw Error(fmt::format("<{}> inside {}, where CIFTI-2 puts it inside <{}>", name,
                              stack.empty() ? std::string("nothing") : "<" + parent() + ">", want));
  }

  CiftiIndexMap& map() { return out.maps.back(); }

  template <class T>
  T number(const char** attrs, const char* element, const char* name, bool required = true,
           T fallback = T{}) {
    const char* v = attribute(attrs, name);
    if (!v) {
      if (!required) return fallback;
      throw Error(fmt::format("<{}> has no {} attribute", element, name));
    }
    std::optional<T> n = parse_header_number<T>(v);
    if (!n) throw Error(fmt::format("<{}> {} is '{}', not a number", element, name, shown(v)));
    return *n;
  }

  std::string string_attribute(const char** attrs, const char* element, const char* name) {
    const char* v = attribute(attrs, name);
    if (!v) throw Error(fmt::format("<{}> has no {} attribute", element, name));
    return v;
  }

  void start(const std::string& name, const char** attrs) {
    if (name == "CIFTI") {
      if (!stack.empty()) throw Error("<CIFTI> inside another element");
      const char* version = attribute(attrs, "Version");
      out.version = version ? version : "";
    } else if (name == "Matrix") {
      require_parent(name, "CIFTI");
    } else if (name == "MatrixIndicesMap") {
      require_parent(name, "Matrix");
      CiftiIndexMap m;
      m.type = string_attribute(attrs, "MatrixIndicesMap", "IndicesMapToDataType");
      const std::string dims =
          string_attribute(attrs, "MatrixIndicesMap", "AppliesToMatrixDimension");
      size_t at = 0;
      while (at <= dims.size()) {
        const size_t comma = std::min(dims.find(',', at), dims.size());
        std::optional<int> d =
            parse_header_number<int>(std::string_view(dims).substr(at, comma - at));
        if (!d || *d < 0 || *d > 1)
          throw Error(fmt::format(
              "<MatrixIndicesMap> AppliesToMatrixDimension is '{}'; a CIFTI-2 matrix has "
              "dimensions 0 and 1",
              shown(dims)));
        m.dimensions.push_back(*d);
        at = comma + 1;
      }
      if (m.type == "CIFTI_INDEX_TYPE_SERIES")
        m.series_points = number<int64_t>(attrs, "MatrixIndicesMap", "NumberOfSeriesPoints");
      out.maps.push_back(std::move(m));
    } else if (name == "NamedMap") {
      require_parent(name, "MatrixIndicesMap");
      if (map().type != "CIFTI_INDEX_TYPE_SCALARS" && map().type != "CIFTI_INDEX_TYPE_LABELS")
        throw Error(fmt::format("<NamedMap> in a map of {}; only scalars and labels have them",
                                map().type));
      if (static_cast<int64_t>(map().names.size()) >= kMaxCiftiMaps)
        throw Error(fmt::format("more than {} named maps", kMaxCiftiMaps));
      map().names.emplace_back();
      map().tables.emplace_back();
    } else if (name == "MapName") {
      require_parent(name, "NamedMap");
      keep_text = true;
      text.clear();
    } else if (name == "LabelTable") {
      require_parent(name, "NamedMap");
    } else if (name == "Label") {
      require_parent(name, "LabelTable");
      label = OverlayLabel{};
      label.key = number<int64_t>(attrs, "Label", "Key");
      const char* channels[4] = {"Red", "Green", "Blue", "Alpha"};
      for (int c = 0; c < 4; ++c) label.rgba[c] = number<float>(attrs, "Label", channels[c]);
      keep_text = true;
      text.clear();
    } else if (name == "BrainModel") {
      require_parent(name, "MatrixIndicesMap");
      if (map().type != "CIFTI_INDEX_TYPE_BRAIN_MODELS")
        throw Error(fmt::format("<BrainModel> in a map of {}", map().type));
      if (map().models.size() >= kMaxBrainModels)
        throw Error(fmt::format("more than {} brain models", kMaxBrainModels));
      CiftiBrainModel m;
      m.offset = number<int64_t>(attrs, "BrainModel", "IndexOffset");
      m.count = number<int64_t>(attrs, "BrainModel", "IndexCount");
      m.structure = string_attribute(attrs, "BrainModel", "BrainStructure");
      const std::string type = string_attribute(attrs, "BrainModel", "ModelType");
      if (type != "CIFTI_MODEL_TYPE_SURFACE" && type != "CIFTI_MODEL_TYPE_VOXELS")
        throw Error(
            fmt::format("<BrainModel> ModelType is '{}' (CIFTI_MODEL_TYPE_SURFACE or "
                        "CIFTI_MODEL_TYPE_VOXELS)",
                        shown(type)));
      m.surface = type == "CIFTI_MODEL_TYPE_SURFACE";
      if (m.surface)
        m.surface_vertices = number<int64_t>(attrs, "BrainModel", "SurfaceNumberOfVertices");
      map().models.push_back(std::move(m));
    } else if (name == "VertexIndices") {
      require_parent(name, "BrainModel");
      if (!map().models.back().vertices.empty())
        throw Error("a <BrainModel> has two <VertexIndices>");
      keep_text = true;
      text.clear();
    } else if (stack.empty()) {
      throw Error(fmt::format("the root element is <{}>, not <CIFTI>", shown(name)));
    }
    stack.push_back(name);
  }

  void end() {
    const std::string name = stack.back();
    stack.pop_back();
    if (name == "MapName") {
      map().names.back() = std::string(trim(text));
    } else if (name == "Label") {
      label.name = std::string(trim(text));
      map().tables.back().push_back(std::move(label));
    } else if (name == "VertexIndices") {
      parse_vertices(map().models.back());
    }
    if (name == "MapName" || name == "Label" || name == "VertexIndices") {
      keep_text = false;
      text.clear();
    }
  }

  void parse_vertices(CiftiBrainModel& m) {
    const char* p = text.data();
    const char* end = p + text.size();
    for (;;) {
      while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
      if (p == end) break;
      if (++vertex_indices > kMaxCiftiBrainordinates)
        throw Error(
            fmt::format("<VertexIndices> list more than {} vertices", kMaxCiftiBrainordinates));
      uint64_t v = 0;
      auto [stop, ec] = std::from_chars(p, end, v);
      if (ec != std::errc() || (stop < end && !std::isspace(static_cast<unsigned char>(*stop))) ||
          v > UINT32_MAX) {
        const char* word_end = p;
        while (word_end < end && !std::isspace(static_cast<unsigned char>(*word_end))) ++word_end;
        throw Error(fmt::format("<VertexIndices> of {} holds '{}', not a vertex index", m.structure,
                                shown(std::string_view(p, word_end - p))));
      }
      m.vertices.push_back(static_cast<uint32_t>(v));
      p = stop;
    }
  }

  void add_text(std::string_view s) {
    if (!keep_text) return;
    if (stack.back() == "VertexIndices" || text.size() < kMaxNameBytes) text.append(s);
  }
};

template <class Fn>
void guarded(void* user, Fn&& fn) {
  auto* self = static_cast<Parser*>(user);
  try {
    fn(*self);
  } catch (const std::exception& e) {
    self->fail(e.what());
  }
}

}  // namespace

CiftiXml parse_cifti_xml(std::string_view xml_text, const std::string& what) {
  auto fail = [&](const std::string& why) {
    throw Error(fmt::format("{}: the CIFTI-2 XML: {}", what, why));
  };
  if (xml_text.size() > static_cast<size_t>(INT_MAX)) fail("larger than 2 GB");
  Parser p;
  const XmlParser xml = make_xml_parser();
  if (!xml) fail("cannot start the XML parser");
  p.xml = xml.get();
  XML_SetUserData(p.xml, &p);
  // No exception may cross expat's C frames: the handlers turn them into a stop.
  XML_SetElementHandler(
      p.xml,
      [](void* u, const char* name, const char** attrs) {
        guarded(u, [&](Parser& self) { self.start(name, attrs); });
      },
      [](void* u, const char*) { guarded(u, [&](Parser& self) { self.end(); }); });
  XML_SetCharacterDataHandler(p.xml, [](void* u, const char* s, int len) {
    guarded(u, [&](Parser& self) { self.add_text({s, static_cast<size_t>(len)}); });
  });
  // CIFTI never needs entities, and they are how XML bombs grow.
  XML_SetEntityDeclHandler(
      p.xml, [](void* u, const char*, int, const char*, int, const char*, const char*, const char*,
                const char*) { static_cast<Parser*>(u)->fail("it declares XML entities"); });
  if (XML_Parse(p.xml, xml_text.data(), static_cast<int>(xml_text.size()), XML_TRUE) ==
      XML_STATUS_ERROR) {
    if (!p.fault.empty()) fail(p.fault);
    fail(fmt::format("{} at line {}", XML_ErrorString(XML_GetErrorCode(p.xml)),
                     XML_GetCurrentLineNumber(p.xml)));
  }
  if (!p.fault.empty()) fail(p.fault);
  return std::move(p.out);
}

}  // namespace imx::detail
