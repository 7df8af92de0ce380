// A quantity string parsed as every Dimension and as a depth. The header
// promises SI values that are finite (or a layerlab::Error): a non-finite
// result is a finding as much as a crash is.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "layerlab/framework/error.h"
#include "layerlab/framework/units.h"

namespace {

constexpr layerlab::Dimension kDimensions[] = {
    layerlab::Dimension::kLength,    layerlab::Dimension::kOpticalPower,     layerlab::Dimension::kAngle,
    layerlab::Dimension::kLuminance, layerlab::Dimension::kAngularFrequency, layerlab::Dimension::kFraction,
    layerlab::Dimension::kTime,      layerlab::Dimension::kFrequency};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string_view text(reinterpret_cast<const char*>(data), size);
  for (layerlab::Dimension d : kDimensions) {
    try {
      double value = layerlab::ParseQuantity(text, d);
      if (!std::isfinite(value)) std::abort();
    } catch (const layerlab::Error&) {
    }
  }
  try {
    layerlab::Depth depth = layerlab::ParseDepth(text);
    if (!std::isfinite(depth.diopters) || depth.diopters < 0) std::abort();
  } catch (const layerlab::Error&) {
  }
  return 0;
}
