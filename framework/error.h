// Errors that tell the user where: "scene.json: /elements/3/pitch: expected ...".
#pragma once

#include <stdexcept>
#include <string>

namespace layerlab {

// Where a value came from: the file and the JSON pointer (RFC 6901) inside it.
struct Location {
  std::string file;     // as the user named it; empty for values built in code
  std::string pointer;  // "" is the whole document

  Location child(const std::string& key) const;
  Location child(size_t index) const;
  // "scene.json: /elements/3/pitch" (the pointer "" is printed as "/").
  std::string str() const;
};

// The one exception type layerlab throws for bad input. what() is the full
// message, location first; message() is the part after the location.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message);
  Error(const Location& where, const std::string& message);

  const std::string& message() const { return message_; }
  const Location& where() const { return where_; }

 private:
  Location where_;
  std::string message_;
};

// Escapes one JSON pointer reference token ("~" -> "~0", "/" -> "~1").
std::string EscapePointerToken(const std::string& token);

}  // namespace layerlab
