#include "layerlab/metrics/psnr.h"

#include <cmath>
#include <limits>

#include "layerlab/framework/error.h"
#include "layerlab/framework/fixed_order_sum.h"

namespace layerlab {

double PsnrDb(double squared_error, size_t samples) {
  if (squared_error <= 0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(double(samples) / squared_error);
}

double ImagePsnrDb(const Image& test, const Image& reference) {
  if (test.width != reference.width || test.height != reference.height ||
      test.channels.size() != reference.channels.size() || test.pixels.size() != reference.pixels.size())
    throw Error("PSNR: the images differ in size (" + std::to_string(test.width) + " x " + std::to_string(test.height) +
                " against " + std::to_string(reference.width) + " x " + std::to_string(reference.height) + ")");
  const size_t n = test.pixels.size();
  return PsnrDb(FixedOrderSquaredDifference(test.pixels.data(), reference.pixels.data(), n), n);
}

}  // namespace layerlab
