// imx::Error in tests: the message code throws (error_of), a check that it throws one holding
// given fragments (expect_error), and EXPECT_CONTAINS for a message's parts.
#pragma once
#include <functional>
#include <initializer_list>
#include <string>

#include <gtest/gtest.h>

#include "intermix/error.hpp"

namespace imx::test {

// The message of the imx::Error that fn throws, or "(no error)".
inline std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

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

#define EXPECT_CONTAINS(text, part) \
  EXPECT_NE(std::string(text).find(part), std::string::npos) << "message: " << (text)
