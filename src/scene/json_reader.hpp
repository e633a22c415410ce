// JsonReader: one JSON value and its path in a scene, with typed getters whose errors name the
// origin, the path and the offending value.
#pragma once
#include <cstddef>
#include <initializer_list>
#include <limits>
#include <new>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "core/limits.hpp"
#include "intermix/error.hpp"
#include "intermix/limits.hpp"

namespace imx::scene_json {

// An interval of allowed numbers; open or closed at either end, unbounded by default.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;

  static Range any() { return {}; }
  static Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  static Range open(double lo, double hi) { return {lo, hi, true, true}; }
  static Range open_closed(double lo, double hi) { return {lo, hi, true, false}; }
  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range non_negative() { return {0.0, std::numeric_limits<double>::infinity()}; }
  // A world position, mm (core/limits.hpp).
  static Range coordinate() { return closed(-kMaxCoordinateMm, kMaxCoordinateMm); }
  // A size or distance, mm.
  static Range length() { return closed(kMinLengthMm, kMaxLengthMm); }
  // A gain such as a light's intensity or a shading coefficient.
  static Range gain() { return closed(0.0, 1000.0); }

  bool contains(double v) const;
  // "is not in [0, 1]", "must be > 0", ...
  std::string violation() const;
};

// A JSON object's key names in the order the format documents them (for unknown-key checks).
using KeyList = std::initializer_list<std::string_view>;

class JsonReader {
 public:
  JsonReader(const nlohmann::json& value, std::string origin, std::string path = {});

  const nlohmann::json& json() const { return *value_; }
  const std::string& origin() const { return origin_; }
  const std::string& path() const { return path_; }

  // Throws imx::Error "origin: path: message".
  [[noreturn]] void fail(std::string_view message) const;
  // The same as imx::FileError with `code` (errno): a file the value names cannot be read.
  [[noreturn]] void fail_file(std::string_view message, int code = 0) const;
  // The same as imx::VolumeTooLarge.
  [[noreturn]] void fail_too_large(std::string_view message) const;
  // Runs `read`, which reads the file this value names, and returns what it returns; what it
  // throws becomes this value's error: a FileError keeps its errno, a VolumeTooLarge its type
  // (a render may go on in bricks), running out of memory names `what` and the budget.
  template <class Read>
  auto reading(const std::string& what, Read&& read) const -> decltype(read()) {
    try {
      return read();
    } catch (const FileError& e) {
      fail_file(e.what(), e.code());
    } catch (const VolumeTooLarge& e) {
      fail_too_large(e.what());
    } catch (const std::bad_alloc&) {
      fail(out_of_memory_message(what));
    } catch (const std::exception& e) {
      fail(e.what());
    }
  }
  // The value for messages: its JSON text, shortened when long.
  std::string text() const;
  // "string \"abc\"", "number 1.5", "object {...}".
  std::string describe() const;

  // Throws unless the value is an object / an array.
  void expect_object() const;
  void expect_array() const;

  // Object access; a missing required key is an error naming the key.
  bool has(std::string_view key) const;
  JsonReader get(std::string_view key) const;
  std::optional<JsonReader> find(std::string_view key) const;
  // Throws for any key not in `known`, suggesting the closest known key.
  void check_keys(KeyList known) const;

  // Array access.
  size_t size() const;
  JsonReader at(size_t index) const;
  std::vector<JsonReader> elements() const;

  // Typed values: each throws on a wrong type, a non-finite number or a value outside `range`.
  double number(Range range = Range::any()) const;
  int integer(int lo, int hi) const;
  bool boolean() const;
  std::string string() const;
  // A string that must be one of `options` (with a suggestion when close).
  std::string choice(KeyList options) const;
  // An array of exactly `n` numbers.
  std::vector<double> numbers(size_t n, Range range = Range::any()) const;
  glm::dvec3 vec3(Range range = Range::any()) const;
  glm::dvec2 vec2(Range range = Range::any()) const;
  // A non-zero vector, normalized.
  glm::dvec3 direction() const;
  // A colour as scene files give it: three display (sRGB) numbers in [0, 1], returned linear.
  glm::vec3 color() const;

 private:
  JsonReader child(const nlohmann::json& value, std::string path) const;

  const nlohmann::json* value_;  // owned by the caller, outlives every reader of the document
  std::string origin_;
  std::string path_;
};

}  // namespace imx::scene_json
