#include "layerlab/lenses/glass_catalog.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include "layerlab/framework/error.h"

namespace layerlab::lenses {
namespace {

constexpr char kSchott[] = "SCHOTT optical glass catalogue, Zemax edition 2017-01-20b";
constexpr char kSultanova[] = "Sultanova, Kasarova, Nikolov, Acta Phys. Pol. A 116, 585 (2009)";

const std::vector<Material>& Catalogue() {
  static const std::vector<Material> catalogue = {
      {"air",
       {0, 0, 0},
       {0, 0, 0},
       0,
       std::numeric_limits<double>::infinity(),
       "relative index: the catalogue indices are relative to air",
       1,
       0},
      {"N-BK7",
       {1.03961212, 0.231792344, 1.01046945},
       {0.00600069867, 0.0200179144, 103.560653},
       0.3e-6,
       2.5e-6,
       kSchott,
       1.51680,
       64.17},
      {"N-SF11",
       {1.73759695, 0.313747346, 1.89878101},
       {0.013188707, 0.0623068142, 155.23629},
       0.37e-6,
       2.5e-6,
       kSchott,
       1.78472,
       25.68},
      {"N-F2",
       {1.39757037, 0.159201403, 1.2686543},
       {0.00995906143, 0.0546931752, 119.248346},
       0.365e-6,
       2.5e-6,
       kSchott,
       1.62005,
       36.43},
      {"N-LAK22",
       {1.14229781, 0.535138441, 1.04088385},
       {0.00585778594, 0.0198546147, 100.834017},
       0.31e-6,
       2.5e-6,
       kSchott,
       1.65113,
       55.89},
      {"N-SF5",
       {1.52481889, 0.187085527, 1.42729015},
       {0.011254756, 0.0588995392, 129.141675},
       0.37e-6,
       2.5e-6,
       kSchott,
       1.67271,
       32.25},
      {"N-BAF10",
       {1.5851495, 0.143559385, 1.08521269},
       {0.00926681282, 0.0424489805, 105.613573},
       0.35e-6,
       2.5e-6,
       kSchott,
       1.67003,
       47.11},
      {"SF5",
       {1.46141885, 0.247713019, 0.949995832},
       {0.0111826126, 0.0508594669, 112.041888},
       0.35e-6,
       2.5e-6,
       kSchott,
       1.67270,
       32.21},
      {"PMMA", {1.1819, 0, 0}, {0.011313, 0, 0}, 0.4368e-6, 1.052e-6, kSultanova, 0, 0},
      {"PC", {1.4182, 0, 0}, {0.021304, 0, 0}, 0.4368e-6, 1.052e-6, kSultanova, 0, 0},
      {"E48R", {1.2969, 0, 0}, {0.011721, 0, 0}, 0.4368e-6, 1.052e-6, kSultanova, 0, 0},
  };
  return catalogue;
}

std::string Nanometers(double meters) {
  char text[32];
  std::snprintf(text, sizeof text, "%g nm", meters * 1e9);
  return text;
}

}  // namespace

double Material::Index(double wavelength_m) const {
  if (IsAir()) return 1.0;
  if (!(wavelength_m >= min_wavelength_m && wavelength_m <= max_wavelength_m)) {
    throw Error(name + ": " + Nanometers(wavelength_m) + " lies outside the range of its dispersion formula, " +
                Nanometers(min_wavelength_m) + " to " + Nanometers(max_wavelength_m) + " (" + source + ")");
  }
  const double l2 = (wavelength_m * 1e6) * (wavelength_m * 1e6);
  double n2 = 1.0;
  for (size_t i = 0; i < sellmeier_b.size(); ++i) n2 += sellmeier_b[i] * l2 / (l2 - sellmeier_c_um2[i]);
  return std::sqrt(n2);
}

const Material& FindMaterial(const std::string& name) {
  for (const Material& m : Catalogue()) {
    if (m.name == name) return m;
  }
  std::string known;
  for (const std::string& n : MaterialNames()) known += (known.empty() ? "" : ", ") + n;
  throw Error("unknown material \"" + name + "\" (the catalogue knows " + known + ")");
}

std::vector<std::string> MaterialNames() {
  std::vector<std::string> names;
  for (const Material& m : Catalogue()) names.push_back(m.name);
  return names;
}

double AbbeNumber(const Material& material) {
  return (material.Index(kLineD_m) - 1.0) / (material.Index(kLineF_m) - material.Index(kLineC_m));
}

}  // namespace layerlab::lenses
