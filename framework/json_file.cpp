#include "layerlab/framework/json_file.h"

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include "layerlab/framework/content_digest.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/file_kind.h"
#include "layerlab/framework/file_read_observer.h"
#include "layerlab/framework/text_file.h"

namespace layerlab {
namespace {

using nlohmann::json;

// Tracks where the parser is, so a duplicate key can be named by its pointer.
class StructureGuard {
 public:
  StructureGuard(std::string file, int max_depth) : file_(std::move(file)), max_depth_(max_depth) {}

  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        if (static_cast<int>(frames_.size()) >= max_depth_)
          throw Error({file_, Pointer()}, "JSON nesting deeper than " + std::to_string(max_depth_) + " levels");
        frames_.push_back({event == json::parse_event_t::array_start, {}, {}, 0});
        break;
      case json::parse_event_t::key: {
        Frame& top = frames_.back();
        std::string key = parsed.get<std::string>();
        if (!top.keys.insert(key).second)
          throw Error({file_, Pointer() + "/" + EscapePointerToken(key)},
                      "duplicate key \"" + key + "\" (each key may appear once per object)");
        top.key = key;
        break;
      }
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        frames_.pop_back();
        CompleteChild();
        break;
      case json::parse_event_t::value:
        CompleteChild();
        break;
    }
    return true;
  }

 private:
  struct Frame {
    bool is_array;
    std::set<std::string> keys;
    std::string key;
    size_t index;
  };

  void CompleteChild() {
    if (!frames_.empty() && frames_.back().is_array) ++frames_.back().index;
  }

  // Pointer of the innermost open container.
  std::string Pointer() const {
    std::string p;
    for (size_t i = 0; i + 1 < frames_.size(); ++i)
      p += "/" + (frames_[i].is_array ? std::to_string(frames_[i].index) : EscapePointerToken(frames_[i].key));
    return p;
  }

  std::string file_;
  int max_depth_;
  std::vector<Frame> frames_;
};

// nlohmann's messages start "[json.exception.parse_error.101] parse error at
// line 3, column 5: "; we give our own position and keep the explanation.
std::string Explanation(std::string what) {
  if (!what.empty() && what[0] == '[') what = what.substr(what.find("] ") + 2);
  if (what.rfind("parse error", 0) == 0) what = what.substr(what.find(": ") + 2);
  return what;
}

// "file:line:column" of a byte offset.
std::string PositionOf(const std::string& text, size_t byte, const std::string& file) {
  size_t line = 1, column = 1;
  for (size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n')
      ++line, column = 1;
    else
      ++column;
  }
  return file + ":" + std::to_string(line) + ":" + std::to_string(column);
}

}  // namespace

json ParseJson(const std::string& text, const std::string& file, const JsonLimits& limits) {
  if (text.size() > limits.max_bytes)
    throw Error({file, ""},
                "file is " + std::to_string(text.size()) + " bytes; the limit is " + std::to_string(limits.max_bytes));
  StructureGuard guard(file, limits.max_depth);
  try {
    return json::parse(text, std::ref(guard));
  } catch (const json::parse_error& e) {
    throw Error(PositionOf(text, e.byte == 0 ? 0 : e.byte - 1, file) + ": malformed JSON: " + Explanation(e.what()));
  } catch (const json::out_of_range& e) {
    // "number overflow parsing '1e400'": nlohmann gives no position; find the literal.
    std::string what = Explanation(e.what());
    size_t open = what.find('\''), close = what.rfind('\'');
    size_t at = 0;
    if (open != std::string::npos && close > open) at = text.find(what.substr(open + 1, close - open - 1));
    throw Error(PositionOf(text, at == std::string::npos ? 0 : at, file) + ": malformed JSON: " + what +
                " (the number is beyond the range of a double)");
  }
}

json ReadJsonFile(const std::string& path, const JsonLimits& limits, FileBytes* bytes) {
  const std::string text = ReadFileText(path, limits.max_bytes);
  if (bytes) *bytes = {text.size(), ContentDigest().add(text).value()};
  return ParseJson(text, path, limits);
}

std::string JsonKindName(const json& value) {
  switch (value.type()) {
    case json::value_t::object:
      return "an object";
    case json::value_t::array:
      return "an array";
    case json::value_t::string:
      return "a string";
    case json::value_t::boolean:
      return "a boolean";
    case json::value_t::null:
      return "null";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
    case json::value_t::number_float:
      return "a number";
    default:
      return "a value";
  }
}

}  // namespace layerlab
