#include "layerlab/lenses/glass_absorption.h"

#include <cmath>
#include <cstdio>
#include <vector>

#include "layerlab/framework/error.h"

namespace layerlab::lenses {
namespace {

struct TablePoint {
  double wavelength_nm;
  double tau_25mm;
};

struct AbsorptionTable {
  const char* material;
  std::vector<TablePoint> points;  // ascending wavelengths
};

constexpr char kSource[] =
    "SCHOTT Zemax catalogue 2017-01-20b, internal transmittance of 25 mm (via refractiveindex.info)";

// SCHOTT internal transmittance tau_i, 25 mm samples (see the header).
const std::vector<AbsorptionTable>& Tables() {
  static const std::vector<AbsorptionTable> tables = {
      {"N-BK7", {{300, 0.050},  {310, 0.250},  {320, 0.520},  {334, 0.780}, {350, 0.920}, {365, 0.971}, {370, 0.977},
                 {380, 0.983},  {390, 0.989},  {400, 0.992},  {405, 0.993}, {420, 0.993}, {436, 0.992}, {460, 0.993},
                 {500, 0.994},  {546, 0.996},  {580, 0.995},  {620, 0.994}, {660, 0.994}, {700, 0.996}, {1060, 0.997},
                 {1530, 0.980}, {1970, 0.840}, {2325, 0.560}, {2500, 0.360}}},
      {"N-SF11",
       {{370, 0.002},
        {380, 0.120},
        {390, 0.390},
        {400, 0.600},
        {405, 0.670},
        {420, 0.810},
        {436, 0.870},
        {460, 0.920},
        {500, 0.953},
        {546, 0.978},
        {580, 0.984},
        {620, 0.981},
        {660, 0.981},
        {700, 0.985},
        {1060, 0.998},
        {1530, 0.985},
        {1970, 0.915},
        {2325, 0.700},
        {2500, 0.620}}},
      {"N-F2", {{365, 0.040}, {370, 0.160},  {380, 0.510},  {390, 0.750},  {400, 0.870},  {405, 0.900}, {420, 0.950},
                {436, 0.963}, {460, 0.973},  {500, 0.984},  {546, 0.992},  {580, 0.993},  {620, 0.991}, {660, 0.990},
                {700, 0.992}, {1060, 0.996}, {1530, 0.977}, {1970, 0.880}, {2325, 0.640}, {2500, 0.480}}},
      {"N-LAK22", {{310, 0.020}, {320, 0.100},  {334, 0.350},  {350, 0.655},  {365, 0.840},  {370, 0.873},
                   {380, 0.920}, {390, 0.950},  {400, 0.964},  {405, 0.968},  {420, 0.973},  {436, 0.975},
                   {460, 0.980}, {500, 0.988},  {546, 0.993},  {580, 0.993},  {620, 0.991},  {660, 0.992},
                   {700, 0.994}, {1060, 0.994}, {1530, 0.978}, {1970, 0.900}, {2325, 0.620}, {2500, 0.370}}},
      {"N-SF5",
       {{370, 0.040},
        {380, 0.330},
        {390, 0.620},
        {400, 0.780},
        {405, 0.830},
        {420, 0.910},
        {436, 0.935},
        {460, 0.956},
        {500, 0.976},
        {546, 0.988},
        {580, 0.991},
        {620, 0.988},
        {660, 0.987},
        {700, 0.989},
        {1060, 0.994},
        {1530, 0.975},
        {1970, 0.880},
        {2325, 0.630},
        {2500, 0.500}}},
      {"N-BAF10",
       {{350, 0.010}, {365, 0.310}, {370, 0.440},  {380, 0.660},  {390, 0.800},  {400, 0.880},  {405, 0.900},
        {420, 0.940}, {436, 0.954}, {460, 0.967},  {500, 0.981},  {546, 0.990},  {580, 0.990},  {620, 0.991},
        {660, 0.990}, {700, 0.994}, {1060, 0.994}, {1530, 0.980}, {1970, 0.920}, {2325, 0.680}, {2500, 0.450}}},
      {"SF5", {{350, 0.310}, {365, 0.730}, {370, 0.800},  {380, 0.880},  {390, 0.920},  {400, 0.950},  {405, 0.959},
               {420, 0.973}, {436, 0.982}, {460, 0.988},  {500, 0.993},  {546, 0.996},  {580, 0.996},  {620, 0.995},
               {660, 0.995}, {700, 0.996}, {1060, 0.996}, {1530, 0.987}, {1970, 0.900}, {2325, 0.740}, {2500, 0.660}}},
  };
  return tables;
}

const AbsorptionTable* TableOf(const Material& material) {
  for (const AbsorptionTable& t : Tables()) {
    if (material.name == t.material) return &t;
  }
  return nullptr;
}

double AlphaPerMeter(double tau_25mm) { return -std::log(tau_25mm) / kAbsorptionReferenceThickness_m; }

}  // namespace

bool HasAbsorptionData(const Material& material) { return TableOf(material) != nullptr; }

double AbsorptionPerMeter(const Material& material, double wavelength_m) {
  const AbsorptionTable* table = TableOf(material);
  if (table == nullptr) return 0.0;
  const double nm = wavelength_m * 1e9;
  const std::vector<TablePoint>& p = table->points;
  if (!(nm >= p.front().wavelength_nm && nm <= p.back().wavelength_nm)) {
    char text[160];
    std::snprintf(text, sizeof text, "%s: %g nm lies outside its internal transmittance table, %g nm to %g nm (",
                  material.name.c_str(), nm, p.front().wavelength_nm, p.back().wavelength_nm);
    throw Error(text + std::string(kSource) + ")");
  }
  size_t i = 1;
  while (i + 1 < p.size() && p[i].wavelength_nm < nm) ++i;
  const double f = (nm - p[i - 1].wavelength_nm) / (p[i].wavelength_nm - p[i - 1].wavelength_nm);
  return (1.0 - f) * AlphaPerMeter(p[i - 1].tau_25mm) + f * AlphaPerMeter(p[i].tau_25mm);
}

double InternalTransmittance(const Material& material, double wavelength_m, double path_m) {
  return std::exp(-AbsorptionPerMeter(material, wavelength_m) * path_m);
}

std::string AbsorptionSource(const Material& material) {
  if (HasAbsorptionData(material)) return kSource;
  return "no published internal transmittance table in the catalogue: absorption not modelled";
}

}  // namespace layerlab::lenses
