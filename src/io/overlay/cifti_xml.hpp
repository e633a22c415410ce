// The XML of a CIFTI-2 header extension, parsed with expat into its index maps, as
// nibabel.cifti2.parse_cifti2 reads them (the elements a surface overlay needs; others, such
// as parcels' and volumes' contents, are checked for their nesting only).
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/overlay/cifti.hpp"

namespace imx::detail {

struct CiftiIndexMap {
  std::vector<int> dimensions;     // AppliesToMatrixDimension: "0", "1" or "0,1"
  std::string type;                // IndicesMapToDataType: CIFTI_INDEX_TYPE_SCALARS, ...
  int64_t series_points = -1;      // NumberOfSeriesPoints (series)
  std::vector<std::string> names;  // MapName of each NamedMap
  std::vector<std::vector<OverlayLabel>> tables;  // LabelTable of each NamedMap (labels)
  std::vector<CiftiBrainModel> models;            // brain models, in the file's order
};

struct CiftiXml {
  std::string version;  // the CIFTI element's Version
  std::vector<CiftiIndexMap> maps;
};

// Parses `xml`; throws imx::Error "WHAT: the CIFTI-2 XML ..." naming the element or attribute
// at fault (XML errors, entity declarations, misplaced elements, numbers that are not numbers,
// more than kMaxCiftiMaps named maps or kMaxCiftiBrainordinates vertex indices).
CiftiXml parse_cifti_xml(std::string_view xml, const std::string& what);

}  // namespace imx::detail
