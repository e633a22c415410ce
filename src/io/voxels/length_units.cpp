#include "io/voxels/length_units.hpp"

namespace imx::detail {

std::optional<double> millimetres_per_unit(std::string_view unit) {
  // Names, symbols and common spellings of one length each: what microscopes' files write.
  static const std::pair<std::string_view, double> kUnits[] = {
      {"angstrom", 1e-7},   {"Å", 1e-7},   {"\u212b", 1e-7},  // U+212B, the Angstrom sign
      {"picometer", 1e-9},  {"pm", 1e-9},  {"nanometer", 1e-6},  {"nm", 1e-6},
      {"micrometer", 1e-3}, {"µm", 1e-3},  // U+00B5 micro sign
      {"μm", 1e-3},         {"um", 1e-3},  {"micron", 1e-3},     {"microns", 1e-3},
      {"millimeter", 1.0},  {"mm", 1.0},   {"centimeter", 10.0}, {"cm", 10.0},
      {"decimeter", 100.0}, {"dm", 100.0}, {"meter", 1000.0},    {"m", 1000.0},
      {"inch", 25.4},       {"in", 25.4},  {"foot", 304.8},      {"ft", 304.8}};
  for (const auto& [name, mm] : kUnits)
    if (unit == name) return mm;
  return std::nullopt;
}

const char* length_units_read() {
  return "angstrom (Å), picometer (pm), nanometer (nm), micrometer (µm, um, micron), "
         "millimeter (mm), centimeter (cm), decimeter (dm), meter (m), inch (in) and foot (ft)";
}

}  // namespace imx::detail
