// imx::Error: the one exception type thrown at API boundaries; its message names the culprit.
#pragma once
#include <stdexcept>
#include <string>

namespace imx {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace imx
