// One cell of a CSV file (RFC 4180): quoted, with its quotes doubled, when it
// holds a comma, a quote or a line break; as it is otherwise.
#pragma once

#include <string>

namespace layerlab {

inline std::string CsvCell(const std::string& cell) {
  if (cell.find_first_of(",\"\r\n") == std::string::npos) return cell;
  std::string quoted = "\"";
  for (char c : cell) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace layerlab
