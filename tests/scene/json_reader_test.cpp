#include "scene/json_reader.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "expect_error.hpp"
#include "linear_time.hpp"
#include "scene/strict_json.hpp"

namespace imx::scene_json {
namespace {

using nlohmann::json;
using test::error_of;

TEST(JsonReader, NonFiniteNumbersAreRejected) {
  // JSON text cannot hold NaN or infinity, but a document built in code can.
  json j = {{"x", std::nan("")}, {"y", std::numeric_limits<double>::infinity()}};
  JsonReader r(j, "s.json", "");
  EXPECT_CONTAINS(error_of([&] { r.get("x").number(); }), "s.json: x: nan is not a finite number");
  EXPECT_CONTAINS(error_of([&] { r.get("y").number(); }), "s.json: y: inf is not a finite number");
  EXPECT_CONTAINS(error_of([&] { r.get("x").integer(0, 10); }), "s.json: x: expected an integer");
}

TEST(JsonReader, PathsAndRanges) {
  json j = json::parse(R"({"a": {"b": [1, 2.5, "z"]}})");
  JsonReader r(j, "s.json");
  JsonReader b = r.get("a").get("b");
  EXPECT_EQ(b.path(), "a.b");
  EXPECT_EQ(b.at(1).path(), "a.b[1]");
  EXPECT_EQ(b.at(1).number(Range::open_closed(2.0, 3.0)), 2.5);
  EXPECT_CONTAINS(error_of([&] { b.at(0).number(Range::open(1.0, 2.0)); }),
                  "s.json: a.b[0]: 1 is not in (1, 2)");
  EXPECT_CONTAINS(error_of([&] { b.at(1).number(Range::non_negative()); }), "(no error)");
  EXPECT_CONTAINS(error_of([&] { b.at(2).number(); }),
                  "s.json: a.b[2]: expected a number, got string \"z\"");
  EXPECT_CONTAINS(error_of([&] { b.at(3); }), "s.json: a.b: has 3 elements");
  EXPECT_CONTAINS(error_of([&] { b.vec3(); }), "a.b[2]: expected a number");
  EXPECT_CONTAINS(error_of([&] { r.get("c"); }), "s.json: missing required key 'c'");
  EXPECT_FALSE(r.find("c").has_value());
  EXPECT_TRUE(r.has("a"));
}

TEST(JsonReader, LongValuesAreShortenedInMessages) {
  json j = json::array();
  for (int i = 0; i < 100; ++i) j.push_back(i);
  JsonReader r(j, "s.json", "big");
  std::string msg = error_of([&] { r.string(); });
  EXPECT_CONTAINS(msg, "...");
  EXPECT_LT(msg.size(), 120u);
}

// Malformed text and numbers beyond a double are nlohmann's own exceptions, of their own types,
// as nlohmann::json::parse throws them: callers name them differently.
TEST(StrictJson, ParseErrorsKeepTheirTypes) {
  EXPECT_THROW(parse_strict_json("{", "m"), nlohmann::json::parse_error);
  EXPECT_THROW(parse_strict_json("[1, 2e400]", "m"), nlohmann::json::out_of_range);
  test::expect_error([] { parse_strict_json(R"({"a": {"b": 1, "b": 2}})", "m"); },
                     {"m: a: key 'b' appears twice in the same object"});
}

// Scene JSON through the strict parser (duplicate keys, depth) at 4 MiB against a sixteenth
// (issue 48, item 3): one object of many keys, and an array of many small objects.
TEST(StrictJson, IsReadInLinearTime) {
  constexpr size_t kBytes = size_t{4} << 20;
  const auto keys = [](size_t bytes) {
    int key = 0;
    std::string s = "{";
    while (s.size() + 40 < bytes) s += fmt::format("\"key_{}\": [1, 2.5, \"x\"], ", key++);
    return s + "\"last\": 0}";
  };
  const auto objects = [](size_t bytes) {
    return test::repeated_to("[", "{\"a\": 1, \"b\": {\"c\": [true, null]}}, ", bytes - 4) + "{}]";
  };
  const auto parse = [](const std::string& text) { parse_strict_json(text, "scene.json"); };
  EXPECT_LE(test::growth_over_linear(parse, keys(kBytes), keys(kBytes / 16)),
            test::kMaxGrowthOverLinear)
      << "keys: time(n) / (16 time(n/16))";
  EXPECT_LE(test::growth_over_linear(parse, objects(kBytes), objects(kBytes / 16)),
            test::kMaxGrowthOverLinear)
      << "objects: time(n) / (16 time(n/16))";
}

}  // namespace
}  // namespace imx::scene_json
