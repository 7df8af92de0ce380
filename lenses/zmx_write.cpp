// WriteZmx (zmx_format.h): a Prescription as the .zmx subset, in millimeters
// when every number reads back exactly in them, else in meters.
#include <charconv>
#include <cmath>
#include <optional>
#include <string>

#include "layerlab/framework/error.h"
#include "layerlab/lenses/zmx_format.h"
#include "layerlab/lenses/zmx_numbers.h"

namespace layerlab::lenses {
namespace {

constexpr size_t kMaxAsphereTerms = 7;  // EVENASPH's PARM 2..8: r^4 .. r^16

// Numbers in one lens unit, noting whether each reads back to the same double.
struct Numbers {
  double meters_per_unit = 1e-3;
  bool exact = true;

  // `value_si` (of dimension length^power) in the lens unit.
  std::string operator()(double value_si, int power) {
    const std::string text = zmx::FormatExact(value_si, power, meters_per_unit);
    const std::optional<double> v = zmx::ParseNumber(text);  // none: beyond a double in this unit
    exact = exact && v && zmx::ToMeters(*v, power, meters_per_unit) == value_si;
    return text;
  }
};

std::string Plain(double value, int digits) {
  char text[64];
  const std::to_chars_result r = std::to_chars(text, text + sizeof text, value, std::chars_format::general, digits);
  return std::string(text, r.ptr);
}

// "GLAS N-BK7 0 0 nd vd": a catalogue glass (solve type 0), nd and vd from its formula for the reader's eye.
std::string GlassLine(const std::string& name) {
  const Material& m = FindMaterial(name);
  return "  GLAS " + m.name + " 0 0 " + Plain(m.Index(kLineD_m), 6) + " " + Plain(AbbeNumber(m), 4);
}

void CheckWritable(const Prescription& p) {
  if (!p.placements.empty()) {
    throw Error("WriteZmx: placements (tilts, decentres) cannot be written: the .zmx subset has no coordinate breaks");
  }
  for (size_t i = 0; i < p.surfaces.size(); ++i) {
    const SurfaceShape& s = p.surfaces[i].shape;
    const std::string at = "WriteZmx: surface " + std::to_string(i) + ": ";
    if (s.fresnel_pitch_m > 0) throw Error(at + "a Fresnel surface has no STANDARD or EVENASPH form");
    if (s.even_asphere.size() > kMaxAsphereTerms) {
      throw Error(at + std::to_string(s.even_asphere.size()) + " aspheric terms; EVENASPH holds r^4 to r^16 (7)");
    }
  }
}

void WriteSurface(const Prescription& p, size_t i, Numbers& number, std::string* out) {
  const PrescriptionSurface& s = p.surfaces[i];
  auto line = [&](const std::string& text) { *out += text + "\r\n"; };
  line("SURF " + std::to_string(i + 1));
  if (p.stop_surface == static_cast<int>(i)) line("  STOP");
  line(s.shape.even_asphere.empty() ? "  TYPE STANDARD" : "  TYPE EVENASPH");
  line("  CURV " + number(s.shape.curvature_per_m, -1));
  if (s.shape.conic != 0) line("  CONI " + number(s.shape.conic, 0));
  if (!s.shape.even_asphere.empty()) line("  PARM 1 0");
  for (size_t k = 0; k < s.shape.even_asphere.size(); ++k) {
    const int n = static_cast<int>(k) + 2;  // the coefficient of r^(2n)
    line("  PARM " + std::to_string(n) + " " + number(s.shape.even_asphere[k], 1 - 2 * n));
  }
  line("  DISZ " + number(s.thickness_m, 1));
  if (s.material != "air") line(GlassLine(s.material));
  if (std::isfinite(s.shape.semi_diameter_m)) {
    line("  DIAM " + number(s.shape.semi_diameter_m, 1) + " 1 0 0 1 \"\"");
  }
}

std::string Write(const Prescription& prescription, const std::string& title, Numbers& number) {
  std::string name = title;
  for (char& c : name) {
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  }
  const char* unit = number.meters_per_unit == 1.0 ? "METER" : "MM";
  std::string out = "MODE SEQ\r\nNAME " + name + "\r\nUNIT " + unit + " X W X CM MR CPMM\r\n";
  out += "SURF 0\r\n  TYPE STANDARD\r\n  CURV 0\r\n  DISZ INFINITY\r\n";
  if (prescription.material_before != "air") out += GlassLine(prescription.material_before) + "\r\n";
  for (size_t i = 0; i < prescription.surfaces.size(); ++i) WriteSurface(prescription, i, number, &out);
  out += "SURF " + std::to_string(prescription.surfaces.size() + 1) + "\r\n  TYPE STANDARD\r\n  CURV 0\r\n  DISZ 0\r\n";
  return out;
}

}  // namespace

std::string WriteZmx(const Prescription& prescription, const std::string& title) {
  const LensSystem checked(prescription);
  CheckWritable(prescription);
  Numbers millimeters{1e-3};
  const std::string in_millimeters = Write(prescription, title, millimeters);
  if (millimeters.exact) return in_millimeters;
  Numbers meters{1.0};  // in meters every double is written as it is
  return Write(prescription, title, meters);
}

}  // namespace layerlab::lenses
