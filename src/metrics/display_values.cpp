#include "metrics/display_values.hpp"

#include <fmt/format.h>

#include "intermix/error.hpp"

namespace imx {

void require_comparable(const Image& a, const Image& b) {
  if (a.width() != b.width() || a.height() != b.height())
    throw Error(fmt::format("images differ in size: {}x{} vs {}x{}", a.width(), a.height(),
                            b.width(), b.height()));
  if (a.empty())
    throw Error(fmt::format("cannot compare empty images: {}x{} vs {}x{}", a.width(), a.height(),
                            b.width(), b.height()));
}

}  // namespace imx
