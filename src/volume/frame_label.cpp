#include <cmath>
#include <string>

#include <fmt/format.h>

#include "intermix/volume.hpp"

namespace imx {

std::string describe_frame(const FrameLabel& label) {
  std::string out;
  auto add = [&](const std::string& part) { out += (out.empty() ? "" : ", ") + part; };
  if (label.time_s) add(fmt::format("t={:.6g} s", *label.time_s));
  if (label.b_value) {
    std::string b = fmt::format("b={:.6g}", *label.b_value);
    if (label.b_vector)
      b += fmt::format(" ({:.4g},{:.4g},{:.4g})", label.b_vector->x, label.b_vector->y,
                       label.b_vector->z);
    add(b);
  }
  if (label.echo_time_ms) add(fmt::format("TE={:.6g} ms", *label.echo_time_ms));
  if (label.trigger_time_ms) add(fmt::format("trigger={:.6g} ms", *label.trigger_time_ms));
  if (!label.image_type.empty()) add(label.image_type);
  return out;
}

}  // namespace imx
