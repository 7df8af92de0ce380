// ReadZmx (zmx_format.h): lines -> raw surfaces in lens units -> Prescription.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "layerlab/framework/error.h"
#include "layerlab/lenses/zmx_format.h"
#include "layerlab/lenses/zmx_numbers.h"
#include "layerlab/lenses/zmx_text.h"

namespace layerlab::lenses {
namespace {

// Lines that do not change the surfaces (zmx_format.h lists why).
const std::set<std::string_view> kIgnored = {
    "VERS", "NAME", "NOTE", "COMM", "PFIL", "LANG", "ENPD", "ENVD", "FNUM", "OBNA", "FLOA", "GFAC", "GCAT", "RAIM",
    "PUSH", "SDMA", "FTYP", "ROPD", "PICB", "XFLN", "YFLN", "FWGN", "VDXN", "VDYN", "VCXN", "VCYN", "VANN", "ZVDX",
    "ZVDY", "ZVCX", "ZVCY", "ZVAN", "WAVM", "WAVN", "WWGN", "WAVL", "WWGT", "PWAV", "POLS", "GLRS", "GSTD", "NSCD",
    "COFN", "BLNK", "TOL",  "MOFF", "HIDE", "MIRR", "SLAB", "POPS", "COAT", "MEMA", "FLAP"};

constexpr int kMaxParm = 8;  // EVENASPH: r^2 .. r^16

struct Line {
  int number = 0;
  std::string_view text;
  std::vector<std::string_view> tokens;
};

struct Value {
  double number = 0.0;
  int line = 0;  // 0: not given
};

struct RawSurface {
  int line = 0;  // the SURF line
  std::string type = "STANDARD";
  Value curv, coni, disz, diam, clap;
  bool disz_infinite = false;
  std::string material = "air";
  Value stop;
  std::map<int, Value> parms;
  std::map<std::string, int, std::less<>> seen;  // keyword -> its line
};

std::vector<std::string_view> Tokens(std::string_view text) {
  std::vector<std::string_view> tokens;
  size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
    const size_t start = i;
    while (i < text.size() && text[i] != ' ' && text[i] != '\t') ++i;
    if (i > start) tokens.push_back(text.substr(start, i - start));
  }
  return tokens;
}

// At most 80 printable ASCII characters of `text`, for a message.
std::string Printable(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (out.size() == 80) return out + "...";
    out += (c >= 0x20 && c < 0x7F) ? c : '?';
  }
  return out;
}

std::string Upper(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

class ZmxReader {
 public:
  explicit ZmxReader(std::string source) : source_(std::move(source)) {}

  Prescription Read(const std::string& text);

 private:
  [[noreturn]] void Fail(int line, const std::string& what) const {
    throw Error(source_ + ":" + std::to_string(line) + ": " + what);
  }
  void HandleLine(const Line& line);
  void HandleSurfaceLine(const Line& line, RawSurface& s);
  void Set(const Line& line, RawSurface& s);
  double Number(const Line& line, size_t index) const;
  std::string Glass(const Line& line) const;
  void CheckEnd(const RawSurface& s, const char* role) const;
  PrescriptionSurface Convert(const RawSurface& s) const;
  std::vector<double> EvenAsphere(const RawSurface& s) const;
  void Validate(const Prescription& p) const;

  std::string source_;
  std::optional<double> meters_per_unit_;
  int unit_line_ = 0;
  int stop_line_ = 0;
  std::vector<RawSurface> surfaces_;
};

double ZmxReader::Number(const Line& line, size_t index) const {
  if (index >= line.tokens.size()) Fail(line.number, std::string(line.tokens[0]) + " needs a number");
  const std::optional<double> v = zmx::ParseNumber(line.tokens[index]);
  if (!v) Fail(line.number, "\"" + Printable(line.tokens[index]) + "\" is not a finite number");
  return *v;
}

std::string ZmxReader::Glass(const Line& line) const {
  if (line.tokens.size() < 2) Fail(line.number, "GLAS needs a glass name");
  const std::string name = Upper(line.tokens[1]);
  if (name == "___BLANK" || name == "MODEL") {
    Fail(line.number, "model glass (" + name + ") is not supported: name a catalogue glass");
  }
  if (name == "MIRROR") Fail(line.number, "mirrors are not supported (refracting surfaces only)");
  std::string known;
  for (const std::string& m : MaterialNames()) {
    if (Upper(m) == name) return m;
    known += (known.empty() ? "" : ", ") + m;
  }
  Fail(line.number, "unknown glass \"" + Printable(line.tokens[1]) + "\" (the catalogue knows " + known + ")");
}

void ZmxReader::Set(const Line& line, RawSurface& s) {
  const std::string_view key = line.tokens[0];
  if (key == "TYPE") {
    const std::string_view type = line.tokens.size() > 1 ? line.tokens[1] : "";
    if (type != "STANDARD" && type != "EVENASPH") {
      Fail(line.number, "surface type " + Printable(type) + " is not supported (STANDARD and EVENASPH only)");
    }
    s.type = type;
  } else if (key == "DISZ" && line.tokens.size() > 1 && line.tokens[1] == "INFINITY") {
    s.disz = {0.0, line.number};
    s.disz_infinite = true;
  } else if (key == "GLAS") {
    s.material = Glass(line);
  } else if (key == "STOP") {
    if (stop_line_ != 0) Fail(line.number, "a second STOP (the first is at line " + std::to_string(stop_line_) + ")");
    stop_line_ = line.number;
    s.stop = {1.0, line.number};
  } else if (key == "CLAP") {
    if (Number(line, 1) != 0) Fail(line.number, "an annular aperture (CLAP with a minimum radius) is not supported");
    s.clap = {Number(line, 2), line.number};
    if (s.clap.number <= 0) Fail(line.number, "expected an aperture radius > 0");
  } else {
    Value& v = key == "CURV" ? s.curv : key == "CONI" ? s.coni : key == "DISZ" ? s.disz : s.diam;
    v = {Number(line, 1), line.number};
    if (key == "DIAM" && v.number < 0) Fail(line.number, "expected a semi-diameter >= 0 (0: no aperture)");
  }
}

void ZmxReader::HandleSurfaceLine(const Line& line, RawSurface& s) {
  const std::string key(line.tokens[0]);
  if (key == "PARM") {
    const double index = Number(line, 1);
    if (!(index >= 1 && index <= kMaxParm && index == static_cast<int>(index))) {
      Fail(line.number, "PARM index " + Printable(line.tokens[1]) + " outside 1 to 8");
    }
    const int n = static_cast<int>(index);
    if (s.parms.count(n)) Fail(line.number, "PARM " + std::to_string(n) + " given twice");
    s.parms[n] = {Number(line, 2), line.number};
    return;
  }
  const auto [at, inserted] = s.seen.emplace(key, line.number);
  if (!inserted) {
    Fail(line.number, key + " given twice in SURF " + std::to_string(surfaces_.size() - 1) + " (first at line " +
                          std::to_string(at->second) + ")");
  }
  Set(line, s);
}

void ZmxReader::HandleLine(const Line& line) {
  const std::string_view key = line.tokens[0];
  if (kIgnored.count(key)) return;
  if (key == "MODE") {
    if (line.tokens.size() < 2 || line.tokens[1] != "SEQ") {
      Fail(line.number, "only sequential files (MODE SEQ) are supported");
    }
  } else if (key == "MNUM") {
    if (Number(line, 1) != 1) Fail(line.number, "multi-configuration files (MNUM > 1) are not supported");
  } else if (key == "OBDC") {
    if (Number(line, 1) != 0 || Number(line, 2) != 0) Fail(line.number, "decentred apertures are not supported");
  } else if (key == "UNIT") {
    if (unit_line_ != 0) Fail(line.number, "a second UNIT (the first is at line " + std::to_string(unit_line_) + ")");
    unit_line_ = line.number;
    meters_per_unit_ = zmx::MetersPerUnit(line.tokens.size() > 1 ? line.tokens[1] : "");
    if (!meters_per_unit_) Fail(line.number, "lens units must be MM, CM, IN or METER");
  } else if (key == "SURF") {
    if (Number(line, 1) != static_cast<double>(surfaces_.size())) {
      Fail(line.number,
           "expected SURF " + std::to_string(surfaces_.size()) + " (surfaces numbered 0, 1, ... in order)");
    }
    surfaces_.emplace_back().line = line.number;
  } else if (key == "TYPE" || key == "CURV" || key == "CONI" || key == "PARM" || key == "DISZ" || key == "GLAS" ||
             key == "DIAM" || key == "STOP" || key == "CLAP") {
    if (surfaces_.empty()) Fail(line.number, std::string(key) + " outside a SURF block");
    HandleSurfaceLine(line, surfaces_.back());
  } else {
    Fail(line.number, "\"" + Printable(line.text) + "\": " + Printable(key) +
                          " is not in the supported .zmx subset (docs/optics.md, \"Real lenses\")");
  }
}

// The object and the image surface: planes, no stop.
void ZmxReader::CheckEnd(const RawSurface& s, const char* role) const {
  if (s.curv.number != 0) Fail(s.curv.line, std::string("the ") + role + " surface must be a plane (CURV 0)");
  for (const auto& [n, v] : s.parms) {
    if (v.number != 0) Fail(v.line, std::string("the ") + role + " surface must be a plane (PARM 0)");
  }
  if (s.stop.line != 0) Fail(s.stop.line, std::string("the stop cannot be the ") + role + " surface");
}

std::vector<double> ZmxReader::EvenAsphere(const RawSurface& s) const {
  const double u = *meters_per_unit_;
  std::vector<double> terms;
  for (const auto& [n, v] : s.parms) {
    if (v.number == 0) continue;
    if (s.type == "STANDARD") {
      Fail(v.line, "PARM " + std::to_string(n) + " on a STANDARD surface (TYPE EVENASPH for an asphere)");
    }
    if (n == 1) {
      Fail(v.line, "PARM 1, the r^2 term, is not supported (the even asphere starts at r^4; with CURV it is no conic)");
    }
    terms.resize(n - 1, 0.0);
    terms[n - 2] = zmx::ToMeters(v.number, 1 - 2 * n, u);
    if (!std::isfinite(terms[n - 2])) Fail(v.line, "the coefficient overflows in meters");
  }
  return terms;
}

PrescriptionSurface ZmxReader::Convert(const RawSurface& s) const {
  const double u = *meters_per_unit_;
  if (s.disz_infinite) Fail(s.disz.line, "DISZ INFINITY is only for the object surface");
  PrescriptionSurface out;
  out.shape.curvature_per_m = zmx::ToMeters(s.curv.number, -1, u);
  out.shape.conic = s.coni.number;
  out.shape.even_asphere = EvenAsphere(s);
  const Value& aperture = s.clap.line != 0 ? s.clap : s.diam;
  if (aperture.number > 0) out.shape.semi_diameter_m = zmx::ToMeters(aperture.number, 1, u);
  out.material = s.material;
  out.thickness_m = zmx::ToMeters(s.disz.number, 1, u);  // lengths shrink or stay (u <= 1 m): no overflow
  if (!std::isfinite(out.shape.curvature_per_m)) Fail(s.curv.line, "the curvature overflows in 1/m");
  return out;
}

// LensSystem's checks, its error moved to the surface's SURF line.
void ZmxReader::Validate(const Prescription& p) const {
  try {
    LensSystem check(p);
  } catch (const Error& e) {
    const std::string& pointer = e.where().pointer;
    int surf = 0;  // "/material_before" belongs to the object surface
    if (pointer.rfind("/surfaces/", 0) == 0) surf = 1 + std::atoi(pointer.c_str() + 10);
    Fail(surfaces_[std::min<size_t>(surf, surfaces_.size() - 1)].line,
         "SURF " + std::to_string(surf) + ": " + e.message() + " (" + pointer + ")");
  }
}

Prescription ZmxReader::Read(const std::string& text) {
  const std::string decoded = zmx::DecodeText(text, source_);
  std::string_view rest = decoded;
  for (int number = 1; !rest.empty(); ++number) {
    const size_t end = rest.find('\n');
    std::string_view raw = rest.substr(0, end);
    rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
    if (!raw.empty() && raw.back() == '\r') raw.remove_suffix(1);
    Line line{number, raw, Tokens(raw)};
    if (!line.tokens.empty()) HandleLine(line);
  }
  if (surfaces_.size() < 3) {
    throw Error(source_ + ": " + std::to_string(surfaces_.size()) +
                " SURF blocks; a lens needs the object (SURF 0), at least one surface and the image");
  }
  if (!meters_per_unit_) meters_per_unit_ = 1e-3;  // Zemax's default lens unit
  CheckEnd(surfaces_.front(), "object");
  CheckEnd(surfaces_.back(), "image");
  Prescription p;
  p.material_before = surfaces_.front().material;
  for (size_t i = 1; i + 1 < surfaces_.size(); ++i) {
    p.surfaces.push_back(Convert(surfaces_[i]));
    if (surfaces_[i].stop.line != 0) p.stop_surface = static_cast<int>(i) - 1;
  }
  Validate(p);
  return p;
}

}  // namespace

Prescription ReadZmx(const std::string& text, const std::string& source_name) {
  return ZmxReader(source_name).Read(text);
}

}  // namespace layerlab::lenses
