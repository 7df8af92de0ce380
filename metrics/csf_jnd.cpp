#include "layerlab/metrics/csf_jnd.h"

#include <cmath>
#include <complex>
#include <numbers>
#include <string>

#include "layerlab/eye/barten_csf.h"
#include "layerlab/eye/spectral_filter.h"
#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

void Check(const Plane& a, const Plane& b, const CsfJndOptions& o) {
  if (a.width != b.width || a.height != b.height)
    throw Error("CSF JND: the images differ in size (" + std::to_string(a.width) + " x " + std::to_string(a.height) +
                " and " + std::to_string(b.width) + " x " + std::to_string(b.height) + ")");
  if (a.width < 1 || a.height < 1 || a.values.size() != static_cast<size_t>(a.width) * a.height ||
      b.values.size() != a.values.size())
    throw Error("CSF JND: an image is empty or its values do not match its size");
  if (!(o.pixel_deg > 0) || !std::isfinite(o.pixel_deg))
    throw Error("CSF JND: pixel_deg " + std::to_string(o.pixel_deg) + ": must be above 0");
  if (!(o.minkowski_exponent >= 1) || !std::isfinite(o.minkowski_exponent))
    throw Error("CSF JND: minkowski_exponent " + std::to_string(o.minkowski_exponent) + ": must be 1 or more");
  for (const Plane* p : {&a, &b})
    for (double v : p->values)
      if (!(v >= 0) || !std::isfinite(v)) throw Error("CSF JND: a luminance that is negative or not finite");
}

// (mean over a period of |sin|^beta)^(1/beta) = (Gamma((beta + 1) / 2) / (sqrt(pi) Gamma(beta / 2 + 1)))^(1/beta).
double SineMinkowskiMean(double beta) {
  return std::pow(std::tgamma((beta + 1) / 2) / (std::sqrt(std::numbers::pi) * std::tgamma(beta / 2 + 1)), 1 / beta);
}

}  // namespace

double CsfJnd(const Plane& reference, const Plane& test, const CsfJndOptions& o) {
  Check(reference, test, o);
  CheckWeight(reference, o.weight, "CSF JND");
  double mean = 0;
  for (double v : reference.values) mean += v;
  mean /= static_cast<double>(reference.values.size());
  if (!(mean > 0)) throw Error("CSF JND: the reference's mean luminance is 0: no contrast is defined");

  std::vector<std::complex<double>> field(reference.values.size());
  for (size_t k = 0; k < field.size(); ++k) field[k] = (test.values[k] - reference.values[k]) / mean;
  BartenConditions eye;
  eye.luminance_cd_m2 = mean;
  eye.field_x_deg = reference.width * o.pixel_deg, eye.field_y_deg = reference.height * o.pixel_deg;
  FilterPeriodic(&field, reference.width, reference.height, o.pixel_deg,
                 [&](double fx, double fy) { return BartenContrastSensitivity(std::hypot(fx, fy), eye); });

  const double beta = o.minkowski_exponent;
  double sum = 0, total = 0;
  for (size_t k = 0; k < field.size(); ++k) {
    const double w = o.weight ? o.weight->values[k] : 1.0;
    sum += w * std::pow(std::abs(field[k].real()), beta), total += w;
  }
  return std::pow(sum / total, 1 / beta) / SineMinkowskiMean(beta);
}

}  // namespace layerlab
