// The key tables at the top of the element files and section readers: a
// markdown table (key, type, default, meaning) in the file's leading comment,
// under a heading line "section: what it is" that starts the comment or
// follows an empty comment line. docs/scene-reference.md is made from them.
#pragma once

#include <string>
#include <vector>

namespace layerlab {

struct KeyRow {
  std::string key, type, default_value, meaning;
  // Made from an option table (solvers/solver_option_table.h): the range, the
  // command-line flag and the Python keyword; empty for a comment's table.
  std::string range, cli_flag, python;
};

struct KeyTable {
  std::string section;  // "thin_lens", "solve", "run.retina", ...
  std::string prose;    // the heading's text after "section: " and the lines after it, paragraphs split by "\n\n"
  std::string file;     // as given, for messages
  std::vector<KeyRow> rows;
  // An option table's: its options that the scene file does not set, listed after the keys.
  std::vector<KeyRow> other_options;
  bool from_option_table = false;
  std::vector<std::string> keys() const;
};

// Every table in the leading comment of `file`; throws layerlab::Error naming
// the file and line for a malformed table.
std::vector<KeyTable> ReadKeyTables(const std::string& file);

// The units a value of `type` (a table's type cell) is written in, from the
// dimension it names ("length", "angle", "depth", ...): "m, cm, mm, um, nm;
// a bare number is m". Empty when the type has no unit.
std::string UnitsOfType(const std::string& type);

}  // namespace layerlab
