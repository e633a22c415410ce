// The PAR text of a Philips PAR/REC pair, parsed as nibabel.parrec parses it: the general
// information by name and the slice table's rows, for parrec_reader.cpp to sort and place.
#pragma once
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace imx::detail {

// Where the values the reader uses sit in a parsed row (one value per number, text as 0).
struct ParColumn {
  enum : size_t {
    kSlice = 0,
    kEcho = 1,
    kDynamic = 2,
    kImageType = 4,
    kPixelBits = 7,
    kReconX = 9,
    kReconY = 10,
    kRescaleIntercept = 11,
    kRescaleSlope = 12,
    kThickness = 22,
    kGap = 23,
    kOrientation = 25,
    kSpacingX = 28,
    kSpacingY = 29,
    kEchoTime = 30,
    kDynamicStart = 31,
    kTriggerTime = 32,
    kBFactor = 33,
    kBValueNumber = 41,  // 4.1 on
    kGradientNumber = 42,
    kGradient = 45,  // ap, fh, rl
  };
};

using ParRow = std::vector<double>;

struct ParHeader {
  std::string version;                                 // "V4", "V4.1", "V4.2"
  std::map<std::string, std::vector<double>> numbers;  // general information, by name
  std::vector<ParRow> rows;                            // the slice table, in file order
};

// The PAR text of `file` as nibabel's _split_header walks it, checked as its _truncation_checks
// check it. Throws imx::Error naming `what` and the line or field nibabel would refuse.
ParHeader read_par_header(const std::filesystem::path& file, const std::string& what);

// The numbers of general information field `name` (the reader's name for it), or null.
const std::vector<double>* par_general(const ParHeader& par, const char* name);

// The same, throwing imx::Error naming the field's PAR `key` when the header has no such line.
const std::vector<double>& require_par_general(const ParHeader& par, const char* name,
                                               const char* key, const std::string& what);

// The one value column `index` holds on every line (nibabel refuses a property that varies).
double unique_par_value(const ParHeader& par, size_t index, const char* name,
                        const std::string& what);

}  // namespace imx::detail
