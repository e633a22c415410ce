// One expat parser, freed with its owner: what every XML reader (VTK XML, GIfTI, CIFTI, OME-XML)
// starts from. In fuzzing builds its hash salt is fixed: expat salts its hash tables from the
// system's randomness, so a fuzz run with a fixed seed would take other paths on each run
// (scripts/fuzz --ci); everywhere else the random salt stays, against hash flooding.
#pragma once
#include <memory>
#include <type_traits>

#include <expat.h>

namespace imx {

using XmlParser = std::unique_ptr<std::remove_pointer_t<XML_Parser>, decltype(&XML_ParserFree)>;

// Null when expat cannot allocate one.
inline XmlParser make_xml_parser() {
  XmlParser parser(XML_ParserCreate(nullptr), &XML_ParserFree);
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
  if (parser) XML_SetHashSalt(parser.get(), 1);
#endif
  return parser;
}

}  // namespace imx
