// Which CIFTI structure a surface file is: what Workbench writes in a GIfTI surface
// (AnatomicalStructurePrimary), else what its name says, else what its vertex count allows.
#include <cctype>
#include <exception>
#include <fstream>
#include <memory>
#include <optional>
#include <type_traits>
#include <vector>

#include <expat.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "intermix/error.hpp"
#include "io/overlay/cifti.hpp"
#include "io/streams/header_text.hpp"
#include "io/streams/input_file.hpp"
#include "io/streams/xml_parser.hpp"

namespace imx::detail {
namespace {

constexpr size_t kMaxMetaBytes = 256;  // of an MD Name or Value: longer ones are not structures

// The AnatomicalStructurePrimary of a GIfTI file: its POINTSET array's, else the file's.
struct MetaScan {
  XML_Parser xml = nullptr;
  std::vector<std::string> stack;
  bool in_pointset = false;
  std::string name, value, *text = nullptr;
  std::optional<std::string> file_level, pointset_level;

  void start(std::string_view element, const char** attrs) {
    if (element == "DataArray") {
      in_pointset = false;
      for (size_t i = 0; attrs[i]; i += 2)
        if (std::string_view(attrs[i]) == "Intent")
          in_pointset = std::string_view(attrs[i + 1]) == "NIFTI_INTENT_POINTSET";
    } else if (element == "MD") {
      name.clear();
      value.clear();
    } else if (element == "Name") {
      text = &name;
    } else if (element == "Value") {
      text = &value;
    }
    stack.emplace_back(element);
  }

  void end() {
    const std::string element = stack.back();
    stack.pop_back();
    text = nullptr;
    if (element != "MD" || std::string(trim(name)) != "AnatomicalStructurePrimary") return;
    // GIFTI > MetaData > MD, or GIFTI > DataArray > MetaData > MD
    if (stack.size() == 2 && stack[0] == "GIFTI") file_level = std::string(trim(value));
    if (stack.size() == 3 && stack[1] == "DataArray" && in_pointset) {
      pointset_level = std::string(trim(value));
      XML_StopParser(xml, XML_FALSE);  // nothing later matters
    }
  }

  void add(std::string_view s) {
    if (text && text->size() < kMaxMetaBytes) text->append(s.substr(0, kMaxMetaBytes));
  }
};

// nullopt when the file is not GIfTI XML or names no structure (the mesh reader reports faults).
std::optional<std::string> gifti_structure(const std::filesystem::path& surface) {
  const std::string ext = lower(surface.extension().string());
  if (ext != ".gii") return std::nullopt;
  std::ifstream in = try_open_input_stream(surface);
  if (!in) return std::nullopt;
  MetaScan scan;
  const XmlParser xml = make_xml_parser();
  if (!xml) return std::nullopt;
  scan.xml = xml.get();
  XML_SetUserData(scan.xml, &scan);
  XML_SetElementHandler(
      scan.xml,
      [](void* u, const char* name, const char** attrs) {
        static_cast<MetaScan*>(u)->start(name, attrs);
      },
      [](void* u, const char*) { static_cast<MetaScan*>(u)->end(); });
  XML_SetCharacterDataHandler(scan.xml, [](void* u, const char* s, int len) {
    static_cast<MetaScan*>(u)->add({s, static_cast<size_t>(len)});
  });
  XML_SetEntityDeclHandler(scan.xml, [](void* u, const char*, int, const char*, int, const char*,
                                        const char*, const char*, const char*) {
    XML_StopParser(static_cast<MetaScan*>(u)->xml, XML_FALSE);
  });
  std::vector<char> buffer(1 << 16);
  for (bool done = false; !done;) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const auto n = static_cast<int>(in.gcount());
    done = n < static_cast<int>(buffer.size());
    if (XML_Parse(scan.xml, buffer.data(), n, done ? XML_TRUE : XML_FALSE) != XML_STATUS_OK) break;
  }
  if (scan.pointset_level) return scan.pointset_level;
  return scan.file_level;
}

// "CortexLeft" -> "CIFTI_STRUCTURE_CORTEX_LEFT" (GIfTI's names are CIFTI's in camel case).
std::string cifti_name(const std::string& gifti) {
  std::string out = "CIFTI_STRUCTURE_";
  for (size_t i = 0; i < gifti.size(); ++i) {
    const auto c = static_cast<unsigned char>(gifti[i]);
    if (i > 0 && std::isupper(c) && std::islower(static_cast<unsigned char>(gifti[i - 1])))
      out += '_';
    out += static_cast<char>(std::toupper(c));
  }
  return out;
}

// CORTEX_LEFT or CORTEX_RIGHT when the file's name says one side only (lh.pial, X.L.surf.gii,
// hemi-L, left_white), else nullopt.
std::optional<std::string> side_by_name(const std::filesystem::path& surface) {
  const std::string name = lower(surface.filename().string());
  bool left = false, right = false;
  size_t at = 0;
  while (at < name.size()) {
    const size_t end = std::min(name.find_first_of("._- ", at), name.size());
    const std::string word = name.substr(at, end - at);
    left = left || word == "l" || word == "lh" || word == "left";
    right = right || word == "r" || word == "rh" || word == "right";
    at = end + 1;
  }
  if (left == right) return std::nullopt;
  return left ? "CIFTI_STRUCTURE_CORTEX_LEFT" : "CIFTI_STRUCTURE_CORTEX_RIGHT";
}

bool has_surface(const CiftiFile& c, const std::string& structure) {
  for (const CiftiBrainModel& m : c.models)
    if (m.surface && m.structure == structure) return true;
  return false;
}

std::string surfaces_of(const CiftiFile& c) {
  std::vector<std::string> names;
  for (const CiftiBrainModel& m : c.models)
    if (m.surface)
      names.push_back(
          fmt::format("{} ({} vertices)", short_structure_name(m.structure), m.surface_vertices));
  return names.empty() ? std::string("no surface structures")
                       : fmt::format("{}", fmt::join(names, ", "));
}

}  // namespace

std::string cifti_structure_of_surface(const CiftiFile& c, const std::filesystem::path& surface,
                                       size_t vertices) {
  const std::string what = c.file.string(), shown_surface = surface.filename().string();
  auto chosen = [&](const std::string& structure, const std::string& because) {
    if (!has_surface(c, structure))
      throw Error(fmt::format("{}: the surface {} is {} ({}), but the file has {}", what,
                              shown_surface, short_structure_name(structure), because,
                              surfaces_of(c)));
    return structure;
  };
  if (!surface.empty()) {
    if (std::optional<std::string> g = gifti_structure(surface); g && !g->empty())
      return chosen(cifti_name(*g), fmt::format("its AnatomicalStructurePrimary is {}", shown(*g)));
    if (std::optional<std::string> side = side_by_name(surface))
      return chosen(*side, "by its name");
  }
  std::vector<std::string> fits;
  for (const CiftiBrainModel& m : c.models)
    if (m.surface && m.surface_vertices == static_cast<int64_t>(vertices))
      fits.push_back(m.structure);
  if (fits.size() == 1) return fits[0];
  throw Error(fmt::format(
      "{}: which of its structures the surface {} ({} vertices) shows is not known: it names "
      "none (no GIfTI AnatomicalStructurePrimary, no lh/rh, L/R or left/right in its name) and "
      "{} of the file's have {} vertices ({}); give the overlay's \"structure\"",
      what, shown_surface.empty() ? std::string("given") : shown_surface, vertices,
      fits.empty() ? "none" : "several", vertices, surfaces_of(c)));
}

}  // namespace imx::detail
