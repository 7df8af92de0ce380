#include "layerlab/metrics/psnr.h"

#include <cmath>
#include <limits>

#include "layerlab/framework/error.h"
#include "layerlab/framework/fixed_order_sum.h"
#include "layerlab/metrics/ssim.h"

namespace layerlab {

double PsnrDb(double squared_error, size_t samples) {
  if (squared_error <= 0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(double(samples) / squared_error);
}

double ImagePsnrDb(const Image& test, const Image& reference, const Plane* weight) {
  if (test.width != reference.width || test.height != reference.height ||
      test.channels.size() != reference.channels.size() || test.pixels.size() != reference.pixels.size())
    throw Error("PSNR: the images differ in size (" + std::to_string(test.width) + " x " + std::to_string(test.height) +
                " against " + std::to_string(reference.width) + " x " + std::to_string(reference.height) + ")");
  const size_t n = test.pixels.size();
  if (!weight) return PsnrDb(FixedOrderSquaredDifference(test.pixels.data(), reference.pixels.data(), n), n);
  const size_t channels = test.channels.size(), pixels = size_t(test.width) * test.height;
  if (weight->values.size() != pixels) throw Error("PSNR: the weight is not of the images' size");
  double sum = 0, total = 0;
  for (size_t k = 0; k < pixels; ++k) {
    double e = 0;
    for (size_t c = 0; c < channels; ++c) {
      const double d = double(test.pixels[k * channels + c]) - reference.pixels[k * channels + c];
      e += d * d;
    }
    sum += weight->values[k] * e, total += weight->values[k] * double(channels);
  }
  if (!(total > 0)) throw Error("PSNR: the weights are all 0");
  return sum <= 0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(total / sum);
}

}  // namespace layerlab
