#include "layerlab/framework/json_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

std::string JsonError(const std::string& text, JsonLimits limits = {}) {
  try {
    ParseJson(text, "in.json", limits);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(JsonFile, MalformedTextGivesLineAndColumn) {
  EXPECT_EQ(JsonError("{\n  \"a\": 1,\n  \"b\": }"),
            "in.json:3:8: malformed JSON: syntax error while parsing value - unexpected '}'; expected '[', '{', or a "
            "literal");
}

TEST(JsonFile, DuplicateKeysAreRefusedWithTheirPointer) {
  EXPECT_EQ(JsonError(R"({"a": 1, "a": 2})"), "in.json: /a: duplicate key \"a\" (each key may appear once per object)");
  EXPECT_EQ(JsonError(R"({"elements": [{"name": "x"}, {"name": "y", "type": "t", "name": "z"}]})"),
            "in.json: /elements/1/name: duplicate key \"name\" (each key may appear once per object)");
  EXPECT_EQ(JsonError(R"({"a": {"b": [1, [2], {"c": 1, "c": 2}]}})"),
            "in.json: /a/b/2/c: duplicate key \"c\" (each key may appear once per object)");
  EXPECT_EQ(JsonError(R"({"a": {"x": 1}, "b": {"x": 1}})"), "");  // same key in sibling objects is fine
}

TEST(JsonFile, NestingAndSizeAreBounded) {
  std::string deep(100, '[');
  deep += std::string(100, ']');
  EXPECT_EQ(JsonError(deep),
            "in.json: "
            "/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/"
            "0/0/0/0/0/0/0/0/0/0/0: JSON nesting deeper than 64 levels");
  JsonLimits small;
  small.max_bytes = 10;
  EXPECT_EQ(JsonError(R"({"a": "0123456789"})", small), "in.json: /: file is 19 bytes; the limit is 10");
}

TEST(JsonFile, HugeNumbersAreRefusedNotInfinite) {
  EXPECT_EQ(
      JsonError("{\n\"f\": 1e400}"),
      "in.json:2:6: malformed JSON: number overflow parsing '1e400' (the number is beyond the range of a double)");
}

TEST(JsonFile, MissingFileIsNamed) {
  try {
    ReadJsonFile("/nonexistent/scene.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("/nonexistent/scene.json: cannot read: ", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace layerlab
