#include "layerlab/tools/key_tables.h"

#include <fstream>
#include <regex>

#include "layerlab/framework/error.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

std::string Trim(const std::string& s) {
  size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

std::vector<std::string> Cells(const std::string& row) {
  std::vector<std::string> cells;
  size_t start = row.find('|') + 1;
  for (size_t bar; (bar = row.find('|', start)) != std::string::npos; start = bar + 1)
    cells.push_back(Trim(row.substr(start, bar - start)));
  return cells;
}

}  // namespace

std::vector<std::string> KeyTable::keys() const {
  std::vector<std::string> out;
  for (const KeyRow& r : rows) out.push_back(r.key);
  return out;
}

std::vector<KeyTable> ReadKeyTables(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw Error(file + ": cannot open");
  static const std::regex heading(R"(^([a-z_][a-z_.]*): (.*)$)");
  std::vector<KeyTable> tables;
  KeyTable current;
  bool in_prose = false, in_table = false, after_blank = true;
  int header_rows = 0;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.rfind("//", 0) != 0) break;  // the leading comment ends
    std::string text = Trim(line.substr(2));
    auto where = [&] { return file + ":" + std::to_string(number) + ": "; };
    if (text.rfind("|", 0) == 0) {
      if (!in_prose && !in_table) throw Error(where() + "a key table needs a heading line \"section: ...\" above it");
      in_prose = false, in_table = true;
      std::vector<std::string> cells = Cells(text);
      if (cells.size() != 4)
        throw Error(where() + "a key table row has 4 cells (key, type, default, meaning), this one " +
                    std::to_string(cells.size()));
      if (header_rows < 2) {
        if (header_rows == 0 &&
            (cells[0] != "key" || cells[1] != "type" || cells[2] != "default" || cells[3] != "meaning"))
          throw Error(where() + "a key table starts with | key | type | default | meaning |");
        ++header_rows;
        continue;
      }
      current.rows.push_back({cells[0], cells[1], cells[2], cells[3], "", "", ""});
      continue;
    }
    if (in_table) {
      tables.push_back(current);
      current = KeyTable{};
      in_table = false, header_rows = 0;
    }
    std::smatch m;
    if (text.empty()) {
      if (in_prose && !current.prose.empty() && current.prose.substr(current.prose.size() - 2) != "\n\n")
        current.prose += "\n\n";
      after_blank = true;
      continue;
    }
    if (after_blank && std::regex_match(text, m, heading)) {
      current = KeyTable{m[1], m[2], file, {}, {}, false};
      in_prose = true;
    } else if (in_prose) {
      current.prose += (current.prose.back() == '\n' ? "" : " ") + text;
    }
    after_blank = false;
  }
  if (in_table) tables.push_back(current);
  for (KeyTable& t : tables)
    while (!t.prose.empty() && t.prose.back() == '\n') t.prose.pop_back();
  return tables;
}

std::string UnitsOfType(const std::string& type) {
  auto has = [&](const char* word) { return type.find(word) != std::string::npos; };
  auto units = [](Dimension d, const std::string& bare) { return AcceptedUnits(d) + "; a bare number is " + bare; };
  if (type.rfind("{", 0) == 0) return "";  // an object: its own keys carry the units
  if (has("depth")) return "D, or a length (" + AcceptedUnits(Dimension::kLength) + "); a bare number is refused";
  if (has("optical power")) return units(Dimension::kOpticalPower, "D");
  if (has("length")) return units(Dimension::kLength, "m");
  if (has("angular frequenc")) return units(Dimension::kAngularFrequency, "cpd");
  if (has("angle")) return units(Dimension::kAngle, "rad");
  if (has("luminance")) return units(Dimension::kLuminance, "cd/m2");
  if (has("fraction")) return "a number, or %";
  if (has("time")) return units(Dimension::kTime, "s");
  if (has("frequency")) return units(Dimension::kFrequency, "Hz");
  return "";
}

}  // namespace layerlab
