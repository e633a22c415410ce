#include "scene/json_reader.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/colour.hpp"
#include "core/edit_distance.hpp"
#include "intermix/error.hpp"

namespace imx::scene_json {
namespace {

constexpr size_t kMaxShownChars = 60;

std::string format_bound(double v) {
  return fmt::format("{}", v);
}

std::string join(KeyList keys) {
  std::string out;
  for (std::string_view k : keys) {
    if (!out.empty()) out += ", ";
    out += k;
  }
  return out;
}

std::vector<std::string> to_strings(KeyList keys) {
  return {keys.begin(), keys.end()};
}

}  // namespace

bool Range::contains(double v) const {
  bool above = lo_open ? v > lo : v >= lo;
  bool below = hi_open ? v < hi : v <= hi;
  return above && below;
}

std::string Range::violation() const {
  bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo && has_hi)
    return fmt::format("is not in {}{}, {}{}", lo_open ? '(' : '[', format_bound(lo),
                       format_bound(hi), hi_open ? ')' : ']');
  if (has_lo) return fmt::format("must be {} {}", lo_open ? ">" : ">=", format_bound(lo));
  if (has_hi) return fmt::format("must be {} {}", hi_open ? "<" : "<=", format_bound(hi));
  return "is out of range";
}

JsonReader::JsonReader(const nlohmann::json& value, std::string origin, std::string path)
    : value_(&value), origin_(std::move(origin)), path_(std::move(path)) {}

JsonReader JsonReader::child(const nlohmann::json& value, std::string path) const {
  return JsonReader(value, origin_, std::move(path));
}

void JsonReader::fail_file(std::string_view message, int code) const {
  if (path_.empty()) throw FileError(fmt::format("{}: {}", origin_, message), code);
  throw FileError(fmt::format("{}: {}: {}", origin_, path_, message), code);
}

void JsonReader::fail_too_large(std::string_view message) const {
  if (path_.empty()) throw VolumeTooLarge(fmt::format("{}: {}", origin_, message));
  throw VolumeTooLarge(fmt::format("{}: {}: {}", origin_, path_, message));
}

void JsonReader::fail(std::string_view message) const {
  if (path_.empty()) throw Error(fmt::format("{}: {}", origin_, message));
  throw Error(fmt::format("{}: {}: {}", origin_, path_, message));
}

std::string JsonReader::text() const {
  if (value_->is_number_float() && !std::isfinite(value_->get<double>()))
    return fmt::format("{}", value_->get<double>());  // JSON text would say null
  std::string s = value_->dump();
  if (s.size() > kMaxShownChars) s = s.substr(0, kMaxShownChars - 3) + "...";
  return s;
}

std::string JsonReader::describe() const {
  // null and booleans are their own text: "null", not "null null".
  if (value_->is_null() || value_->is_boolean()) return text();
  return fmt::format("{} {}", value_->type_name(), text());
}

void JsonReader::expect_object() const {
  if (!value_->is_object()) fail("expected an object, got " + describe());
}

void JsonReader::expect_array() const {
  if (!value_->is_array()) fail("expected an array, got " + describe());
}

bool JsonReader::has(std::string_view key) const {
  return value_->is_object() && value_->contains(key);
}

JsonReader JsonReader::get(std::string_view key) const {
  expect_object();
  auto it = value_->find(key);
  if (it == value_->end()) fail(fmt::format("missing required key '{}'", key));
  return child(*it, path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key));
}

std::optional<JsonReader> JsonReader::find(std::string_view key) const {
  expect_object();
  if (!value_->contains(key)) return std::nullopt;
  return get(key);
}

void JsonReader::check_keys(KeyList known) const {
  expect_object();
  for (const auto& item : value_->items()) {
    bool ok = false;
    for (std::string_view k : known) ok = ok || k == item.key();
    if (ok) continue;
    JsonReader bad = child(item.value(), path_.empty() ? item.key() : path_ + "." + item.key());
    std::string hint = did_you_mean(item.key(), to_strings(known));
    if (hint.empty()) hint = " (known keys: " + join(known) + ")";
    bad.fail("unknown key" + hint);
  }
}

size_t JsonReader::size() const {
  expect_array();
  return value_->size();
}

JsonReader JsonReader::at(size_t index) const {
  expect_array();
  if (index >= value_->size())
    fail(fmt::format("has {} elements, needs at least {}", value_->size(), index + 1));
  return child((*value_)[index], fmt::format("{}[{}]", path_, index));
}

std::vector<JsonReader> JsonReader::elements() const {
  std::vector<JsonReader> out;
  for (size_t i = 0; i < size(); ++i) out.push_back(at(i));
  return out;
}

double JsonReader::number(Range range) const {
  if (!value_->is_number()) fail("expected a number, got " + describe());
  double v = value_->get<double>();
  if (!std::isfinite(v)) fail(text() + " is not a finite number");
  // The renderer computes in float: a larger number becomes inf, and NaN downstream.
  if (std::abs(v) > std::numeric_limits<float>::max())
    fail(fmt::format("{} is too large: numbers are used as floats (at most {:g})", text(),
                     std::numeric_limits<float>::max()));
  if (!range.contains(v)) fail(text() + " " + range.violation());
  return v;
}

int JsonReader::integer(int lo, int hi) const {
  if (!value_->is_number()) fail("expected an integer, got " + describe());
  double v = value_->get<double>();
  if (!std::isfinite(v) || v != std::floor(v)) fail("expected an integer, got " + describe());
  if (v < lo || v > hi) fail(text() + " " + Range::closed(lo, hi).violation());
  return static_cast<int>(v);
}

bool JsonReader::boolean() const {
  if (!value_->is_boolean()) fail("expected true or false, got " + describe());
  return value_->get<bool>();
}

std::string JsonReader::string() const {
  if (!value_->is_string()) fail("expected a string, got " + describe());
  return value_->get<std::string>();
}

std::string JsonReader::choice(KeyList options) const {
  std::string s = string();
  for (std::string_view o : options)
    if (o == s) return s;
  std::string hint = did_you_mean(s, to_strings(options));
  fail(fmt::format("{} is not one of {}{}", text(), join(options), hint));
}

std::vector<double> JsonReader::numbers(size_t n, Range range) const {
  if (!value_->is_array() || value_->size() != n)
    fail(fmt::format("expected an array of {} numbers, got {}", n, describe()));
  std::vector<double> out;
  for (size_t i = 0; i < n; ++i) out.push_back(at(i).number(range));
  return out;
}

glm::dvec3 JsonReader::vec3(Range range) const {
  std::vector<double> v = numbers(3, range);
  return {v[0], v[1], v[2]};
}

glm::dvec2 JsonReader::vec2(Range range) const {
  std::vector<double> v = numbers(2, range);
  return {v[0], v[1]};
}

glm::dvec3 JsonReader::direction() const {
  glm::dvec3 v = vec3();
  double len = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  if (!(len > 1e-12) || !std::isfinite(len))
    fail(text() + " is not a usable direction (zero length)");
  return v / len;
}

glm::vec3 JsonReader::color() const {
  return display_to_linear(glm::vec3(vec3(Range::closed(0.0, 1.0))));
}

}  // namespace imx::scene_json
