// expect_error: runs code that must throw imx::Error whose message holds given fragments.
#pragma once
#include <initializer_list>
#include <string>

#include <gtest/gtest.h>

#include "intermix/error.hpp"

namespace imx::test {

// Returns the message, after checking it contains every fragment.
template <class Fn>
std::string expect_error(Fn&& fn, std::initializer_list<std::string> fragments) {
  std::string message;
  try {
    fn();
    ADD_FAILURE() << "expected an imx::Error";
    return message;
  } catch (const imx::Error& e) {
    message = e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected an imx::Error, got another exception: " << e.what();
    return e.what();
  }
  for (const std::string& f : fragments)
    EXPECT_NE(message.find(f), std::string::npos) << "'" << f << "' missing from: " << message;
  return message;
}

}  // namespace imx::test
