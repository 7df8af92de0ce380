#include "layerlab/elements/spectral.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "layerlab/framework/polarization.h"

namespace layerlab {

Rgb ReadSpectralFraction(Params& params, const std::string& key, double fallback) {
  if (!params.has(key) || !params.raw(key).is_object()) return params.fraction_rgb(key, fallback);

  Params table = params.object(key);
  const nlohmann::json& wavelengths = table.raw("wavelengths");
  const nlohmann::json& values = table.raw("values");
  table.check_all_read();
  if (!wavelengths.is_array() || wavelengths.size() < 2)
    table.fail("wavelengths", "expected an array of at least two wavelengths");
  if (!values.is_array() || values.size() != wavelengths.size())
    table.fail("values",
               "expected an array with one fraction per wavelength (" + std::to_string(wavelengths.size()) + ")");

  std::vector<double> nm(wavelengths.size()), fraction(values.size());
  for (size_t i = 0; i < nm.size(); ++i) {
    // One-entry objects so that errors point at /.../wavelengths/i or /.../values/i.
    std::string index = std::to_string(i);
    Params wavelength(nlohmann::json{{index, wavelengths[i]}}, table.where("wavelengths"));
    Params value(nlohmann::json{{index, values[i]}}, table.where("values"));
    nm[i] = wavelength.quantity(index, Dimension::kLength);
    fraction[i] = value.fraction_rgb(index)[0];
    if (!(nm[i] > 0)) table.fail("wavelengths", "wavelengths must be positive");
    if (i > 0 && !(nm[i] > nm[i - 1])) table.fail("wavelengths", "wavelengths must increase");
  }

  Rgb out{};
  for (size_t c = 0; c < 3; ++c) {
    double w = kChannelWavelengths[c];
    if (w < nm.front() || w > nm.back())
      table.fail("wavelengths", "the table covers " + FormatFixed(nm.front() * 1e9, 0) + " to " +
                                    FormatFixed(nm.back() * 1e9, 0) + " nm but channel " + kChannelNames[c] +
                                    " is at " + FormatFixed(w * 1e9, 0) + " nm");
    size_t hi = std::upper_bound(nm.begin(), nm.end(), w) - nm.begin();
    hi = std::min(hi, nm.size() - 1);
    size_t lo = hi - 1;
    double t = (w - nm[lo]) / (nm[hi] - nm[lo]);
    out[c] = fraction[lo] + t * (fraction[hi] - fraction[lo]);
  }
  return out;
}

}  // namespace layerlab
