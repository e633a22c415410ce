// imx::Error: the one exception type thrown at API boundaries; its message names the culprit.
#pragma once
#include <stdexcept>
#include <string>

namespace imx {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// Thrown by render() when RenderOptions::cancel was set: not a failure, the frame is dropped.
class Cancelled : public Error {
 public:
  Cancelled() : Error("rendering cancelled") {}
};

}  // namespace imx
