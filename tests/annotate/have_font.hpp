// Whether the annotation font is installed: the text tests say what to install when it is not.
#pragma once
#include "annotate/text_raster.hpp"
#include "intermix/error.hpp"

namespace imx::test {

inline bool have_font() {
  try {
    find_font();
    return true;
  } catch (const Error&) {
    return false;
  }
}

}  // namespace imx::test
