// The transform formats' table of the format registry: read_transform_file chooses its
// reader here.
#pragma once
#include <span>

#include "io/registry/format_registry.hpp"
#include "registration/transform_file.hpp"

namespace imx::detail {

struct TransformFileFormat {
  FormatInfo info;
  TransformFormat format;
};

std::span<const TransformFileFormat> transform_formats_table();

}  // namespace imx::detail
