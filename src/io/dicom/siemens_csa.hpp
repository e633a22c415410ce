// Siemens' CSA headers (private elements (0029,1010) and (0029,1020)): named lists of text values
// that hold what classic Siemens files keep nowhere else (a mosaic's slice normal and tile count).
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace imx::detail {

// The elements of a CSA header (format "SV10" or the older unsigned one), each name with its
// non-empty values. Malformed or truncated bytes give what was read before the fault; never reads
// outside `bytes`.
std::map<std::string, std::vector<std::string>> parse_csa_header(const std::string& bytes);

// The numbers of element `name`, nullopt when it is absent or any value is not a finite number.
std::optional<std::vector<double>> csa_numbers(
    const std::map<std::string, std::vector<std::string>>& csa, const std::string& name);

}  // namespace imx::detail
